#!/usr/bin/env bash
# Front plans: each pass's plan recorded in the results file and shown by report, exported
# as a plan file and replayed from it and from the results file with the same operations at
# every frame and the oracle's pairs; --repeat-plan free marks the frames whose passes
# differ; bad plans are refused naming the file, line and field (docs/usage.md "Plans").
set -u
cdbench=$1
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$root/tests/cli/harness.sh"
python=/usr/bin/python3  # with h5py, to read the results files
[[ -x $python ]] || python=python3

d=$tmp/plans
mkdir -p "$d"
scene=(--device cpu --quiet --scene funnel --set res=12 --set frames=10)
steps() { grep -v '^#' "$1"; }  # a plan file's header and frame lines, without comments
# same_frames A B COLUMN...: the /frames columns of two results files are equal row by row.
same_frames() {
  "$python" -c "
import h5py, sys
a, b = (h5py.File(p, 'r')['frames'] for p in sys.argv[1:3])
bad = [c for c in sys.argv[3:] if list(a[c][()]) != list(b[c][()])]
print('differ:', *bad) if bad else print('same')
sys.exit(1 if bad else 0)" "$@"
}
# same_steps NAME A B: two plan files list the same frames and steps.
same_steps() {
  if diff <(steps "$2") <(steps "$3") >"$tmp/diff"; then echo "ok   $1"; else fail "$1"; sed 's/^/    /' "$tmp/diff" | head; fi
}

# --- recorded: two passes, the second replaying the first ---
check "two passes: the second replays the first's plan" 0 \
  "^  plan        pass 1 replayed pass 0's plan \(--repeat-plan replay\): each frame's mean is over the same operations" -- \
  "$cdbench" run "${scene[@]}" --repeat 2 --out "$d/r.h5"
check "report lists each pass's plan" 0 \
  "^\| $d/r.h5 \| c \| 1 \| replay of pass 0 \| build: 0; update: [^|]+; generate: [^|]+; restructure: [^|]+ \| yes \|$" -- \
  "$cdbench" report "$d/r.h5"
has "report: the first pass planned adaptively" "$tmp/out" "^\| $d/r.h5 \| c \| 0 \| adaptive \| build: 0; update: "
has "report's table says how the passes were planned" "$tmp/out" "\| pass 0 replayed \|"
check "report --plan exports pass 0" 0 "^cdbench-plan 1$" -- "$cdbench" report --plan "$d/r.h5"
cp "$tmp/out" "$d/r.txt"
has "the plan file has one line per frame" "$d/r.txt" "^9 refit self="
[[ $(grep -cE '^[0-9]+ ' "$d/r.txt") -eq 10 ]] && echo "ok   ten frame lines" || fail "frame lines: $(grep -cE '^[0-9]+ ' "$d/r.txt")"
"$cdbench" report --plan "$d/r.h5:c:1" >"$d/r1.txt"
same_steps "pass 1 ran pass 0's steps" "$d/r.txt" "$d/r1.txt"

# --- replayed from the plan file and from the results file: same steps, exact pairs ---
check "replay from a plan file, checked against the oracle" 0 "check +10 frames against the oracle: recall min 1\.000000" -- \
  "$cdbench" run "${scene[@]}" --front-cycle "$d/r.txt" --check every --out "$d/text.h5"
has "the run says it replayed the file" "$tmp/out" "^  plan        the pass replayed $d/r.txt \(--front-cycle\)"
"$cdbench" report --plan "$d/text.h5" >"$d/text.txt"
same_steps "replay from text: the recorded step at every frame" "$d/r.txt" "$d/text.txt"
check "replay from text: the recording's ops and pairs per frame" 0 "^same$" -- same_frames "$d/r.h5" "$d/text.h5" frame op pairs
check "replay from a results file" 0 "check +10 frames against the oracle: recall min 1\.000000" -- \
  "$cdbench" run "${scene[@]}" --front-cycle "$d/r.h5" --repeat 2 --check every --out "$d/h5.h5"
has "every pass replayed it" "$tmp/out" "^  plan        every pass replayed $d/r.h5 \(pipeline c, pass 0\) \(--front-cycle\)"
"$cdbench" report --plan "$d/h5.h5:c:1" >"$d/h5.txt"
same_steps "replay from .h5: the recorded step at every frame" "$d/r.txt" "$d/h5.txt"
check "replay from .h5: the recording's ops and pairs per frame" 0 "^same$" -- same_frames "$d/r.h5" "$d/h5.h5" frame op pairs
check "report names the replayed plan" 0 "\| $d/h5.h5 \| c \| 1 \| replay of $d/r.h5 \(pipeline c, pass 0\) \| " -- \
  "$cdbench" report "$d/h5.h5"

# --- every operation, by hand: pipeline c restructures what its own inspection finds ---
cat >"$d/hand.txt" <<'EOF'
cdbench-plan 1
# every operation pipeline c has
0 build self=generate
1 refit self=preserve
2 refit self=update inspect
3 refit self=restructure decision=restructure
4 refit self=generate inspect
5 refit self=preserve
6 refit self=update
7 refit self=preserve
EOF
degraded=(--restructure-quality 0 --restructure-min-leaves 8)
check "a plan of every operation replays exactly" 0 "check +8 frames against the oracle: recall min 1\.000000" -- \
  "$cdbench" run "${scene[@]}" --frames 0:8 "${degraded[@]}" --front-cycle "$d/hand.txt" --check every --out "$d/hand.h5"
"$cdbench" report --plan "$d/hand.h5" >"$d/hand-ran.txt"
# A plan that names no probe probes on the preserve before each update, and records it.
sed -E 's/^([15] refit self=preserve)$/\1 probe/' "$d/hand.txt" >"$d/hand-probed.txt"
same_steps "the hand plan's steps ran as written, with the probes before its updates" "$d/hand-probed.txt" "$d/hand-ran.txt"
check "report's outline of the hand plan" 0 "\| build: 0; update: 2,6; generate: 4; restructure: 3 \|" -- "$cdbench" report "$d/hand.h5"
check "a recorded pipeline a plan replays on b" 0 "check +8 frames" -- \
  "$cdbench" run "${scene[@]}" --frames 0:8 --pipeline a --out "$d/a.h5" --check every
check "... on pipeline b" 0 "check +8 frames against the oracle: recall min 1\.000000" -- \
  "$cdbench" run "${scene[@]}" --frames 0:8 --pipeline b --front-cycle "$d/a.h5:a" --check every --out "$d/b.h5"
"$cdbench" report --plan "$d/a.h5" >"$d/a.txt"
"$cdbench" report --plan "$d/b.h5" >"$d/b.txt"
same_steps "b ran a's steps" "$d/a.txt" "$d/b.txt"

# --- {pipeline}: an A/B of pipelines, each replaying its own recording ---
check "two pipelines recorded" 0 "results: $d/ab-c.h5" -- "$cdbench" run "${scene[@]}" --pipeline a,c --out "$d/ab-{pipeline}.h5"
check "each replays its own plan" 0 "results: $d/ab2-c.h5" -- \
  "$cdbench" run "${scene[@]}" --pipeline a,c --front-cycle "$d/ab-{pipeline}.h5" --out "$d/ab2-{pipeline}.h5"
for p in a c; do
  "$cdbench" report --plan "$d/ab-$p.h5" >"$d/ab-$p.txt"
  "$cdbench" report --plan "$d/ab2-$p.h5" >"$d/ab2-$p.txt"
  same_steps "pipeline $p replayed its own recording" "$d/ab-$p.txt" "$d/ab2-$p.txt"
done

# --- --repeat-plan free: each pass plans; the frames whose passes differ are marked ---
check "free passes plan for themselves" 0 "^  plan        each pass planned its own \(--repeat-plan free\)" -- \
  "$cdbench" run "${scene[@]}" --repeat 3 --repeat-plan free --out "$d/free.h5"
printed=$(grep -oE "free\): [0-9]+ of" "$tmp/out" | grep -oE "[0-9]+" || echo 0)
# plan_mixed counts the passes whose /plans row differs from the last pass's; an op joined by
# | only where some did; the summary counts the frames, as the run's line does.
check "free passes: plan_mixed, op and the summary agree with /plans" 0 "^consistent$" -- "$python" -c "
import h5py, sys
f = h5py.File(sys.argv[1], 'r')
p, fr = f['plans'], f['frames']
cols = ['trees', 'self', 'inter', 'rigid_self', 'decision', 'inspect', 'probe']
rows = {(int(a), int(b)): tuple(p[c][i] for c in cols) for i, (a, b) in enumerate(zip(p['pass'][()], p['frame'][()]))}
last = max(a for a, _ in rows)
ok = last == 2
for k, frame in enumerate(fr['frame'][()]):
    differ = sum(rows[(a, int(frame))] != rows[(last, int(frame))] for a in range(last))
    op = fr['op'][k].decode()
    ok = ok and fr['plan_mixed'][k] == differ and (('|' in op) <= (differ > 0))
mixed = int(sum(fr['plan_mixed'][()] > 0))
mode = f.attrs['repeat_plan']
mode = mode.decode() if isinstance(mode, bytes) else mode
ok = ok and mode == 'free' and int(f['summary'].attrs['plan_mixed_frames']) == mixed == int(sys.argv[2])
print('consistent' if ok else 'inconsistent')" "$d/free.h5" "$printed"
check "report says how free passes went" 0 "\| free, (passes agree|[0-9]+ frames mixed) \|" -- "$cdbench" report "$d/free.h5"
has "report's free passes planned adaptively" "$tmp/out" "^\| $d/free.h5 \| c \| 2 \| adaptive \| build: 0; .* \| (yes|no: frames [0-9,-]+) \|$"

# --- refused, naming the file, line and field ---
printf 'cdbench-plan 1\n0 build self=generate\n1 refit self=updte\n' >"$d/bad.txt"
check "unknown operation" 2 "bad.txt line 3 field 3 \('self=updte'\): unknown operation 'updte' \(generate, preserve, update, restructure\)" -- \
  "$cdbench" run "${scene[@]}" --front-cycle "$d/bad.txt"
if grep -qE "^(scene|pipeline|frame)" "$tmp/out"; then fail "work began before the refusal"; else echo "ok   refused before any work"; fi
printf 'cdbench-plan 1\n0 build self=generate\n1 refit\n2 refit self=preserve extra\n' >"$d/bad.txt"
check "a field that is no field" 2 "bad.txt line 4 field 4 \('extra'\): expected QUERY=OP" -- "$cdbench" run "${scene[@]}" --front-cycle "$d/bad.txt"
printf '0 build self=generate\n' >"$d/bad.txt"
check "no header" 2 "bad.txt line 1: not a cdbench plan file: expected the header 'cdbench-plan 1'" -- \
  "$cdbench" run "${scene[@]}" --front-cycle "$d/bad.txt"
check "c's restructure on pipeline a" 2 "hand.txt line 5 \(frame 2\): restructures, Formula 2 decisions and inspections are pipeline c's" -- \
  "$cdbench" run "${scene[@]}" --frames 0:8 --pipeline a --front-cycle "$d/hand.txt"
check "more frames than recorded" 2 "hand.txt: the plan records 8 frames \(0 to 7\), the run's frames 0:10 are 10" -- \
  "$cdbench" run "${scene[@]}" --front-cycle "$d/hand.txt"
check "another first frame" 2 "hand.txt line 3 \(frame 0\): the plan starts at frame 0, the run at frame 2" -- \
  "$cdbench" run "${scene[@]}" --frames 2:6 --front-cycle "$d/hand.txt"
check "another scene's queries" 1 "a.txt line [0-9]+ \(frame 0\): query inter runs in this scene, and the plan gives it no operation" -- \
  "$cdbench" run --device cpu --quiet --scene funnel-inter --set res=12 --frames 0:4 --pipeline a --front-cycle "$d/a.txt"
check "no such plan" 2 "nope.txt: no such file" -- "$cdbench" run "${scene[@]}" --front-cycle "$d/nope.txt"
check "another pipeline's results unnamed" 2 "holds pipeline a's plans, not c's: name the pipeline to replay its plan on c \($d/a.h5:a\)" -- \
  "$cdbench" run "${scene[@]}" --front-cycle "$d/a.h5"
check "a pass not run" 2 "$d/r.h5: pipeline c ran passes 0 to 1; there is no pass 4" -- "$cdbench" run "${scene[@]}" --front-cycle "$d/r.h5:c:4"
check "a pipeline without fronts" 2 "pipeline bvh has no front plan to replay" -- "$cdbench" run "${scene[@]}" --pipeline bvh --front-cycle "$d/r.txt"
check "verify replays no plan" 2 "a recorded plan replays on one pipeline" -- "$cdbench" verify --device cpu --frames 0:2 --front-cycle "$d/r.txt"
check "--repeat-plan takes replay or free" 2 "repeat-plan" -- "$cdbench" run "${scene[@]}" --repeat-plan sometimes
"$cdbench" run "${scene[@]}" --pipeline bvh --frames 0:2 --out "$d/bvh.h5" >/dev/null 2>&1
check "report --plan of a run without plans" 1 "bvh.h5: no plans recorded \(pipeline bvh has no front plan" -- "$cdbench" report --plan "$d/bvh.h5"
check "report --plan checks a plan file" 1 "bad.txt line 1: not a cdbench plan file" -- "$cdbench" report --plan "$d/bad.txt"

finish plan
