#!/usr/bin/env bash
# docs/extending.md: the example pipeline through the CLI, and an outside method's pairs
# checked against the oracle (verify --write-pairs, verify --pairs), frame by frame.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

scene=(--device cpu --scene funnel --set res=16 --frames 0:6)

# The example pipeline goes through the factory like every pipeline.
check "help lists the example pipeline as an example" 0 "^  example-sap +EXAMPLE" -- "$cdbench" run --help
check "run the example pipeline" 0 "^pipeline: example-sap on cpu" -- "$cdbench" run "${scene[@]}" --quiet --pipeline example-sap
check "verify the example pipeline" 0 "example-sap +exact \(6 frames\)" -- "$cdbench" verify "${scene[@]}" --pipelines example-sap
check "verify the example pipeline, co-vertex filtering" 0 "example-sap +exact" -- "$cdbench" verify "${scene[@]}" --pipelines example-sap --skip-adjacent

# --pipelines takes a comma list, as run --pipeline does, or spaces.
check "verify --pipelines b,c" 0 "all pipelines match the oracle" -- "$cdbench" verify "${scene[@]}" --pipelines b,c
has "b,c checks b" "$tmp/out" "^  b +exact"
has "b,c checks c" "$tmp/out" "^  c +exact"
check "verify --pipelines b c" 0 "^  c +exact" -- "$cdbench" verify "${scene[@]}" --pipelines b c
check "verify --pipelines b,foo: usage" 2 "unknown pipeline 'foo'" -- "$cdbench" verify "${scene[@]}" --pipelines b,foo

# The oracle's pairs, written and read back.
oracle=$tmp/oracle
check "write the oracle's pairs" 0 "wrote the oracle's pairs of 6 frames" -- "$cdbench" verify "${scene[@]}" --write-pairs "$oracle"
for f in 0 1 2 3 4 5; do [[ -s $oracle/frame_000$f.txt ]] || fail "no $oracle/frame_000$f.txt"; done
has "the file says what it holds" "$oracle/frame_0003.txt" "^# cdbench verify --write-pairs: the oracle's pairs of scene funnel, frame 3"
has "the file holds pairs" "$oracle/frame_0003.txt" "^[0-9]+ [0-9]+$"
check "the oracle's pairs verify" 0 "verify: the pairs match the oracle" -- "$cdbench" verify "${scene[@]}" --pairs "$oracle"
has "every frame reported" "$tmp/out" "^  pairs frame 5 frame_0005.txt: exact"
check "a subrange of the files verifies" 0 "the pairs match the oracle" -- "$cdbench" verify --device cpu --scene funnel --set res=16 --frames 2:4 --pairs "$oracle"
check "other options, other pairs" 1 "pairs frame 0 frame_0000.txt: MISMATCH" -- "$cdbench" verify "${scene[@]}" --pairs "$oracle" --skip-adjacent

# One pair dropped and a bogus one added in frame 3: the frame, the missed and the extra pair.
edited=$tmp/edited
cp -r "$oracle" "$edited"
triangles=$(sed -nE 's/.*\(([0-9]+) triangles\).*/\1/p' "$oracle/frame_0003.txt")
dropped=$(grep -m1 -E '^[0-9]+ [0-9]+$' "$oracle/frame_0003.txt")
bogus="0 $((triangles - 1))"
if grep -qx "$bogus" "$oracle/frame_0003.txt"; then fail "pick another bogus pair: $bogus is real"; fi
grep -vx "$dropped" "$oracle/frame_0003.txt" >"$edited/frame_0003.txt"
echo "$((triangles - 1)) 0" >>"$edited/frame_0003.txt"
check "a dropped and a bogus pair fail" 1 "pairs frame 3 frame_0003.txt: MISMATCH: .* 1 missed, 1 extra, 0 duplicates" -- \
  "$cdbench" verify "${scene[@]}" --pairs "$edited"
has "the missed pair is named" "$tmp/out" "^    missed \(${dropped/ /, }\)$"
has "the extra pair is named" "$tmp/out" "^    extra \(${bogus/ /, }\)$"
has "the other frames are exact" "$tmp/out" "^  pairs frame 4 frame_0004.txt: exact"
has "the summary counts them" "$tmp/out" "MISMATCH in 1 of 6 frames, 0 unreadable, .*: 1 missed, 1 extra, 0 duplicates"
has "verify failed" "$tmp/out" "^verify: FAILED"

# A pair listed twice (reversed) is a duplicate, and fails.
cp "$oracle/frame_0003.txt" "$edited/frame_0003.txt"
read -r a b <<<"$dropped"
echo "$b $a" >>"$edited/frame_0001.txt"
check "a duplicate fails" 1 "pairs frame 1 frame_0001.txt: MISMATCH: .* 0 missed, 0 extra, 1 duplicates" -- \
  "$cdbench" verify "${scene[@]}" --pairs "$edited"
has "the duplicate is named" "$tmp/out" "^    duplicate \($a, $b\)$"

# Malformed files name the file and line.
cp "$oracle/frame_0001.txt" "$edited/frame_0001.txt"
line=$(($(wc -l <"$oracle/frame_0002.txt") + 1))
echo "7 x" >>"$edited/frame_0002.txt"
check "a malformed line names file and line" 1 "frame_0002.txt:$line: expected two triangle indices, got '7 x'" -- \
  "$cdbench" verify "${scene[@]}" --pairs "$edited"
has "the frames after it are still checked" "$tmp/out" "^  pairs frame 5 frame_0005.txt: exact"
cp "$oracle/frame_0002.txt" "$edited/frame_0002.txt"
echo "0 $triangles" >>"$edited/frame_0004.txt"
check "an index out of range names file and line" 1 "frame_0004.txt:[0-9]+: triangle $triangles out of range \(the scene has $triangles triangles" -- \
  "$cdbench" verify "${scene[@]}" --pairs "$edited"
rm "$edited/frame_0004.txt"
check "a missing frame file" 1 "no pairs file for frame 4" -- "$cdbench" verify "${scene[@]}" --pairs "$edited"
check "no such directory: usage" 2 "--pairs $tmp/nowhere: not a directory" -- "$cdbench" verify "${scene[@]}" --pairs "$tmp/nowhere"

# Binary files, and other names matched in natural order.
check "write binary pairs" 0 "wrote the oracle's pairs" -- "$cdbench" verify "${scene[@]}" --write-pairs "$tmp/bin" --pairs-format bin
[[ -s $tmp/bin/frame_0002.bin ]] && echo "ok   binary files written" || fail "no $tmp/bin/frame_0002.bin"
check "binary pairs verify" 0 "the pairs match the oracle" -- "$cdbench" verify "${scene[@]}" --pairs "$tmp/bin"
mkdir "$tmp/named"
for f in 0 1 2 3 4 5; do cp "$oracle/frame_000$f.txt" "$tmp/named/step$((f * 5)).txt"; done
check "natural order matches step0 .. step25" 0 "pairs frame 2 step10.txt: exact" -- "$cdbench" verify "${scene[@]}" --pairs "$tmp/named"

# An outside program (tests/cli/outside_pairs.py, nothing of cdbench) reads the exported
# OBJ frames, builds its boxes as the doc says, and its pairs are exactly the oracle's.
check "export the frames as OBJ" 0 "wrote 3 frames of funnel" -- "$cdbench" scenes generate funnel --set res=4 --set frames=3 --out "$tmp/objs"
"$python" "$root/tests/cli/outside_pairs.py" "$tmp/objs" "$tmp/outside" || fail "outside_pairs.py failed"
check "an outside program's pairs verify" 0 "the pairs match the oracle" -- "$cdbench" verify --device cpu --scene "$tmp/objs" --pairs "$tmp/outside"
has "its files matched in natural order" "$tmp/out" "^  pairs frame 2 pairs2.txt: exact, [1-9][0-9]* pairs"

finish extending
