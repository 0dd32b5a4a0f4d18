#!/usr/bin/env bash
# CLI smoke and bad-input tests: exit codes and messages that name the file, frame and field.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
read_results=("$python" "$root/scripts/read_results.py")

check "run default scene on cpu" 0 "summary: 19 frames measured" -- "$cdbench" run --device cpu --quiet
check "run prints environment" 0 "commit [0-9a-f]+" -- "$cdbench" run --device cpu --quiet --frames 0:2
# A busy host, made busy here: one spinning process per core while a run samples the load.
hogs=()
for _ in $(seq "$(nproc)"); do (while :; do :; done) & hogs+=($!); done
check "a run on a busy host says so" 0 "^warning: the host is busy before the run \\([0-9]+% of its [0-9]+ cores in use by other work\\)" -- \
  "$cdbench" run --device cpu --quiet --frames 0:2 --load-window-ms 300 --out "$tmp/busy-host.h5"
kill "${hogs[@]}" 2>/dev/null; wait "${hogs[@]}" 2>/dev/null
check "report flags the run made on a busy host" 0 "busy-host\\.h5 \\|.*poor conditions: host busy before the run \\([0-9]+%\\)" -- \
  "$cdbench" report "$tmp/busy-host.h5"
"$cdbench" run --device cpu --quiet --frames 0:2 --load-window-ms 0 --out "$tmp/quiet.h5" >/dev/null 2>&1
check "--load-window-ms 0 samples nothing" 0 "^absent$" -- "$python" -c \
  'import h5py, math, sys; v = h5py.File(sys.argv[1]).attrs["host_busy_before"]; print("absent" if math.isnan(v) else v)' "$tmp/quiet.h5"
check "verify all pipelines" 0 "all pipelines match the oracle" -- "$cdbench" verify --device cpu --frames 0:5
check "verify with sweep oracle" 0 "sort-and-sweep" -- "$cdbench" verify --device cpu --frames 0:2 --brute-limit 10
check "unknown pipeline" 2 "unknown pipeline 'nope'" -- "$cdbench" run --device cpu --pipeline nope
check "front cycle auto" 0 "summary: 2 frames measured" -- "$cdbench" run --device cpu --quiet --frames 0:3 --front-cycle auto
check "front cycle K" 0 "summary: 2 frames measured" -- "$cdbench" run --device cpu --quiet --frames 0:3 --front-cycle 3
check "options a pipeline ignores are said" 0 "^warning: --front-cycle, --restructure-quality do not apply to grid \\(front pipelines only; restructuring pipelines only: c\\): ignored there" -- \
  "$cdbench" run --device cpu --quiet --frames 0:2 --pipeline grid --front-cycle 4 --restructure-quality 9
check "a restructure option given to b is said" 0 "^warning: --restructure-quality does not apply to b " -- \
  "$cdbench" run --device cpu --quiet --frames 0:2 --pipeline b,c --restructure-quality 9
if grep -q "does not apply to c" "$tmp/out"; then fail "a restructure option given to c was called ignored"; else echo "ok   c takes the restructure option"; fi
check "verify says which pipelines ignore an option" 0 "^warning: --refit-every does not apply to grid \\(BVH pipelines only" -- \
  "$cdbench" verify --device cpu --frames 0:2 --pipelines bvh,grid --refit-every 1
if grep -q "apply to bvh" "$tmp/out"; then fail "--refit-every given to bvh was called ignored"; else echo "ok   bvh takes --refit-every"; fi
check "front cycle neither auto nor K" 2 "auto, a positive whole number of frames or a plan file, not '0'" -- "$cdbench" run --device cpu --frames 0:3 --front-cycle 0
check "unknown scene" 2 "unknown scene 'nowhere'" -- "$cdbench" run --device cpu --scene nowhere
check "frame range past the end" 2 "only 20 frames" -- "$cdbench" run --device cpu --frames 0:99
check "bad frame range" 2 "expected A:B" -- "$cdbench" run --device cpu --frames x:y
check "--repeat 0 says what it expects" 2 "^--repeat: expected a whole number from 1 to 4294967295, not '0'" -- "$cdbench" run --device cpu --repeat 0
check "--box-margin inf refused" 2 "^--box-margin: expected a finite number >= 0, not 'inf'" -- "$cdbench" run --device cpu --box-margin inf
check "--box-margin -1 refused" 2 "^--box-margin: expected a finite number >= 0, not '-1'" -- "$cdbench" run --device cpu --box-margin -1
check "--max-noise nan refused" 2 "^--max-noise: expected a finite number >= 0, not 'nan'" -- "$cdbench" run --device cpu --max-noise nan
check "sweep --gpus 0 refused" 2 "^--gpus: expected a whole number from 1 to 1024, not '0'" -- "$cdbench" sweep x.json --out "$tmp/sw" --gpus 0
printf '{"generator": "funnel", "params": {"res": 8, "frames": 2}, "objects": [{"name": "a", "faces": [0, 4294967306]}]}' >"$tmp/wrap.json"
check "descriptor face count past uint32 refused, not wrapped" 1 "/objects/0/faces/1: 4294967306 is beyond the largest face index" -- "$cdbench" scenes info "$tmp/wrap.json"
check "frame index past uint32" 2 "beyond the largest frame index" -- "$cdbench" run --device cpu --frames 0:99999999999999999999
check "one frame left to the warm-up, said" 0 "^warning: --frames '2' gives 1 frame, none after --warmup 1: the summary takes in the first frame" -- "$cdbench" run --device cpu --quiet --frames 2
check "--warmup-ms nan refused" 2 "^--warmup-ms: expected a finite number >= 0, not 'nan'" -- "$cdbench" run --device cpu --warmup-ms nan
check "warm-up frames said" 0 "^  warm-up     [1-9][0-9]* frames run untimed first \\(--warmup-ms 1\\)" -- "$cdbench" run --device cpu --quiet --frames 0:4 --warmup-ms 1
check "warm-up wraps to the first frame" 0 "^  warm-up     ([3-9]|[1-9][0-9]+) frames run untimed first \\(--warmup-ms 300\\)" -- "$cdbench" run --device cpu --quiet --frames 0:2 --warmup-ms 300
check "kept frames: the warm-up ends with a pass" 0 "^  warm-up     4 frames run untimed first \\(--warmup-ms 1\\)" -- "$cdbench" run --device cpu --quiet --frames 0:4 --repeat 2 --warmup-ms 1
"$cdbench" run --device cpu --quiet --frames 0:4 --repeat 2 --warmup-ms 1 --out "$tmp/warm.h5" >/dev/null 2>&1
if "$python" -c 'import h5py, sys; sys.exit(int(h5py.File(sys.argv[1])["summary"].attrs["warmup_frames"]) != 4)' "$tmp/warm.h5"; then
  echo "ok   the results file counts the warm-up frames"
else
  fail "the results file counts the warm-up frames (want 4)"
fi
check "report lists the warm-up frames" 0 "warm\\.h5,.*,replay,,0,4,[0-9.]+," -- "$cdbench" report "$tmp/warm.h5" --csv
check "no warm-up with --warmup-ms 0" 0 "summary: 3 frames measured" -- "$cdbench" run --device cpu --quiet --frames 0:4 --warmup-ms 0
if grep -q "warm-up  " "$tmp/out"; then fail "--warmup-ms 0 still warmed up"; else echo "ok   --warmup-ms 0 runs no warm-up"; fi
check "one frame with --warmup 0" 0 "summary: 1 frames measured \\(first 0 left out" -- "$cdbench" run --device cpu --quiet --frames 2 --warmup 0

# Exit codes (docs/usage.md): 0 ok, 1 failure, 2 usage.
check "version names the release" 0 "^cdbench [0-9]+\.[0-9]+\.[0-9]+$" -- "$cdbench" --version
has "version names the commit" "$tmp/out" "^commit +[0-9a-f]{12}(-dirty)?$"
has "version names the CUDA toolkit or its absence" "$tmp/out" "^cuda +(nvcc [0-9.]+|none \(built without CUDA)"
has "version names the build type" "$tmp/out" "^build +(Release|Debug|RelWithDebInfo|MinSizeRel), "
check "unknown option is a usage error" 2 "no-such-option" -- "$cdbench" run --no-such-option
check "bad option value is a usage error" 2 "--device" -- "$cdbench" run --device gpu
check "missing subcommand is a usage error" 2 "subcommand" -- "$cdbench"
check "unknown pipeline in a list: usage, before any run" 2 "unknown pipeline 'foo'" -- "$cdbench" run --device cpu --pipeline b,foo
if grep -qE "^(scene|pipeline|frame) " "$tmp/out"; then fail "pipeline b ran before foo was rejected"; else echo "ok   nothing ran before the bad name was found"; fi
check "a mistyped command names the nearest" 2 "^cdbench: error: unknown command 'runn' \\(did you mean run\\?\\)" -- "$cdbench" runn --device cpu
check "a command far from any is named" 2 "^cdbench: error: unknown command 'xyzzy'; the commands: run, verify" -- "$cdbench" xyzzy
check "verify takes --pipeline as run does" 0 "^  bvh +exact \\(2 frames\\)" -- "$cdbench" verify --device cpu --frames 0:2 --pipeline bvh
check "verify checks every pipeline once" 0 "all pipelines match the oracle" -- "$cdbench" verify --device cpu --frames 0:2
if grep -qE "^  (static|restructure) " "$tmp/out"; then fail "verify ran an alias (static, restructure) beside b and c"; else echo "ok   no alias run twice"; fi
check "verify runs a pipeline named twice once, under both names" 0 "^  b = static +exact \\(2 frames\\)" -- \
  "$cdbench" verify --device cpu --frames 0:2 --pipeline b,static,restructure,c,c
has "verify shows an alias given first under both names" "$tmp/out" "^  restructure = c +exact \\(2 frames\\)"
[[ $(grep -cE "^  [a-z= ]+ +exact \\(" "$tmp/out") -eq 2 ]] && echo "ok   verify ran two pipelines for five names" ||
  fail "verify ran other than two pipelines for b,static,restructure,c,c"
for cmd in run verify; do
  check "$cmd --help says --frames 3 is frame 3 alone" 0 "frame 3 alone, not three frames" -- "$cdbench" "$cmd" --help
done
check "verify rejects an unknown pipeline first" 2 "unknown pipeline 'foo'" -- "$cdbench" verify --device cpu --pipelines b foo
check "default pipeline is c" 0 "^pipeline: c on cpu" -- "$cdbench" run --device cpu --quiet --frames 0:2
check "help groups the options" 0 "^Tuning \\(speed only\\):" -- "$cdbench" run --help
has "help has a scene group" "$tmp/out" "^Scene:"
has "help has a pipeline group" "$tmp/out" "^Pipeline:"
for cmd in "" run verify scenes sweep report; do
  COLUMNS=100 "$cdbench" $cmd --help >"$tmp/help.txt" 2>&1
  long=$(awk 'length > 100' "$tmp/help.txt" | wc -l)
  if [[ $long -eq 0 ]]; then echo "ok   ${cmd:-cdbench} --help fits 100 columns"; else fail "${cmd:-cdbench} --help: $long lines over 100 columns"; awk 'length > 100' "$tmp/help.txt" | head -3; fi
done
check "out names a directory" 2 "--out $tmp/outdir/: names a directory" -- "$cdbench" run --device cpu --frames 0:2 --out "$tmp/outdir/"
touch "$tmp/plainfile"
# An empty name (an unset shell variable) is a mistake in the call, not "no file".
for call in "run --device cpu --out" "verify --device cpu --write-pairs" "verify --device cpu --pairs" \
            "sweep x.json --out" "scenes generate funnel --out" "run --device cpu --scene"; do
  # shellcheck disable=SC2086
  check "$call '' refused" 2 "^--${call##*--}: expected a name, not an empty string$" -- "$cdbench" $call ""
done
check "out under a file" 1 "--out $tmp/plainfile/r.h5: cannot create directory" -- "$cdbench" run --device cpu --frames 0:2 --out "$tmp/plainfile/r.h5"
check "out where nothing can be written" 1 "--out /proc/cdbench-r.h5: cannot write in directory /proc" -- "$cdbench" run --device cpu --frames 0:2 --out /proc/cdbench-r.h5
if grep -q "HDF5" "$tmp/out"; then fail "raw HDF5 errors printed"; else echo "ok   no HDF5 error stack"; fi

check "pipeline c runs and decides" 0 "formula 2 +[0-9]+ refit, [0-9]+ restructure" -- "$cdbench" run --device cpu --quiet --pipeline c --front-cycle 1 --restructure-quality 0 --restructure-min-leaves 8 --threshold-refit 0 --threshold-build 1
check "verify with co-vertex filtering" 0 "all pipelines match the oracle" -- "$cdbench" verify --device cpu --frames 0:3 --skip-adjacent
check "verify with co-vertex filtering, sweep oracle" 0 "all pipelines match the oracle" -- "$cdbench" verify --device cpu --frames 0:2 --skip-adjacent --brute-limit 10
check "scene objects and queries" 0 "query       inter cloth - ball" -- "$cdbench" scenes info funnel-inter --set frames=1
check "scenes info takes --scene as run does" 0 "query       inter cloth - ball" -- \
  "$cdbench" scenes info --scene funnel-inter --set frames=1
# scenes info --json: the text's fields as one object, the numbers exact.
"$cdbench" scenes info funnel-inter --set frames=2 --set res=8 --json >"$tmp/info.json" 2>"$tmp/info.err"
check "scenes info --json has the text's fields" 0 "^funnel-inter 2 frames, inter cloth-[a-z]+, boxes ok, motion null then [0-9.e-]+$" -- \
  "$python" -c "import json, sys; j = json.load(open(sys.argv[1])); f = j['frame_extents']; print(j['scene'], j['frames'], 'frames, inter ' + '-'.join(j['queries']['inter'][0]) + ',', 'boxes ok,' if all(len(e['box_min']) == 3 and all(a <= b for a, b in zip(e['box_min'], e['box_max'])) for e in f) else 'boxes bad,', 'motion', json.dumps(f[0]['motion_mean']), 'then', f[1]['motion_mean'])" "$tmp/info.json"
check "scenes info --json agrees with the text" 0 "^triangles [0-9]+ [0-9]+ same$" -- \
  bash -c "t=\$('$cdbench' scenes info funnel-inter --set frames=2 --set res=8 | awk '/^triangles/ {print \$2}'); j=\$('$python' -c \"import json; print(json.load(open('$tmp/info.json'))['triangles'])\"); echo triangles \$t \$j \$([[ \$t == \$j ]] && echo same || echo differ)"
check "declared queries verify" 0 "all pipelines match the oracle" -- "$cdbench" verify --device cpu --scene funnel-inter --frames 0:3
# Scenes from packaged models (scripts/install-deps.sh --scenes --scenes-extra; CI installs them).
check "MD2 keyframes scene" 0 "^frames +198" -- "$cdbench" scenes info sydney-md2
check "MD2 keyframes verify" 0 "all pipelines match the oracle" -- "$cdbench" verify --device cpu --scene sydney-md2 --frames 0:3
check "crowd scales with --set count" 0 "^triangles +10252" -- "$cdbench" scenes info crowd --set count=2 --set frames=2
check "crowd verify" 0 "all pipelines match the oracle" -- "$cdbench" verify --device cpu --scene crowd --set count=4 --set frames=3
check "rigid part of a scene" 0 "object +bunny +faces 7938..77604 +rigid" -- "$cdbench" scenes info bunny-drop
check "scans extracted into the cache" 0 "object +armadillo +faces 88928..140928 +rigid" -- env CDBENCH_CACHE="$tmp/cache" "$cdbench" scenes info elephant-armadillo
printf '{"frame_count": 2, "parts": [{"name": "b", "mesh": {"file": "/usr/share/glmark2/models/bunny.obj"}, "motion": {"velocity": [0, "up", 0]}}]}' >"$tmp/badmotion.json"
check "bad rigid motion names the JSON path" 1 "badmotion.json: /parts/0/motion/velocity/1: must be a number" -- "$cdbench" run --device cpu --scene "$tmp/badmotion.json"
printf '{"generator": "funnel", "params": {"frames": 2}, "queries": {"self": ["cloth"], "inter": [["cloth", "rocket"]]}}' >"$tmp/badq.json"
check "query names an unknown object" 1 "/queries/inter/0/1: unknown object 'rocket'" -- "$cdbench" run --device cpu --scene "$tmp/badq.json"
printf '{"generator": "soup", "params": {"triangles": 10}, "queries": {"self": ["x"]}}' >"$tmp/noobj.json"
check "queries need objects" 1 "no objects to query" -- "$cdbench" run --device cpu --scene "$tmp/noobj.json"
mkdir -p "$tmp/oor" "$tmp/negidx" "$tmp/quad" "$tmp/garbage" "$tmp/trunc"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' >"$tmp/oor/frame_0000.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n' >"$tmp/negidx/frame_0000.obj"
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n' >"$tmp/quad/frame_0000.obj"
head -c 3000 /dev/urandom >"$tmp/garbage/frame_0000.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2' >"$tmp/trunc/frame_0000.obj"
check "face index out of range names file" 1 "oor/frame_0000.obj: frame 0, line 4: vertex index 7 out of range" -- "$cdbench" run --device cpu --scene "$tmp/oor"
check "negative face index out of range names file" 1 "negidx/frame_0000.obj: frame 0, line 4: vertex index -9 out of range" -- "$cdbench" run --device cpu --scene "$tmp/negidx"
check "polygons are triangulated and said so" 0 "1 polygon faces triangulated \\(2 triangles" -- "$cdbench" run --device cpu --scene "$tmp/quad"
check "binary garbage names file" 1 "garbage/frame_0000.obj: " -- "$cdbench" run --device cpu --scene "$tmp/garbage"
check "truncated OBJ names file" 1 "trunc/frame_0000.obj: " -- "$cdbench" run --device cpu --scene "$tmp/trunc"
check "scene directory with a trailing slash keeps its name" 0 "scene: quad " -- "$cdbench" run --device cpu --scene "$tmp/quad/"
# The oracle judges the scene's double positions: floats keep every pair (recall 1) and add
# the few whose boxes touch within a rounding (precision just below 1).
check "check every frame: recall 1, precision near 1" 0 "check +20 frames against the oracle: recall min 1.000000, precision min (0\\.99[0-9]+|1\\.000000), 0 missed" -- "$cdbench" run --device cpu --quiet --pipeline c --check every
# A 1K-triangle sheet with millimetre edges moved 1e7 out: fp32 blurs it (and says so before
# the run), fp64 keeps exactly the double geometry's pairs and draws no warning.
far=(--scene cloth-wave --set res=24 --set frames=3 --set placement.scale=0.025 --set placement.offset=1e7)
check "fp32 far out: warned before the run" 0 "^warning: float spacing 1 at the largest coordinate 1e\\+07 .*--box-precision fp64" -- "$cdbench" run --device cpu --quiet --pipeline c --frames 0:2 "${far[@]}"
check "fp32 far out: recall 1, blurred" 0 "check +2 frames against the oracle: recall min 1.000000, precision min 0\\.0[0-9]+, 0 missed" -- "$cdbench" run --device cpu --quiet --pipeline c --frames 0:2 --check every "${far[@]}"
check "fp64 far out: the double geometry's pairs" 0 "check +2 frames against the oracle: recall min 1.000000, precision min 1.000000, 0 missed, 0 false positives" -- "$cdbench" run --device cpu --quiet --pipeline c --frames 0:2 --check every "${far[@]}" --box-precision fp64
"$cdbench" run --device cpu --quiet --pipeline grid --frames 0:1 --warmup 0 "${far[@]}" --box-precision fp64 >"$tmp/fp64.out" 2>&1
if grep -q "warning: float spacing" "$tmp/fp64.out"; then fail "fp64 far out: no precision warning"; else echo "ok   fp64 far out: no precision warning"; fi
check "check every 5th frame, co-vertex filtered" 0 "check +4 frames against the oracle: recall min 1.000000" -- "$cdbench" run --device cpu --quiet --pipeline grid --check 5 --skip-adjacent
check "check with declared queries" 0 "check +3 frames against the oracle: recall min 1.000000, precision min 1.000000" -- "$cdbench" run --device cpu --quiet --scene funnel-inter --frames 0:3 --pipeline static --check every
check "check counts true contacts" 0 "contacts +[0-9]+ of [0-9]+ checked pairs truly intersect: contact precision 0\\.[0-9]+, min 0\\.[0-9]+" -- "$cdbench" run --device cpu --quiet --frames 0:3 --pipeline static --check every
check "contacts without co-vertex pairs" 0 "contacts +[0-9]+ of [0-9]+ checked pairs truly intersect" -- "$cdbench" run --device cpu --quiet --frames 0:3 --pipeline hash --check every --skip-adjacent
check "contacts into a results file" 0 "results: " -- "$cdbench" run --device cpu --quiet --frames 0:2 --check every --out "$tmp/contacts.h5"
check "contacts in the results file" 0 "contacts +[0-9]+ of [0-9]+ checked pairs: contact precision 0\\.[0-9]+" -- "${read_results[@]}" --summary "$tmp/contacts.h5"
check "contact columns in the results file" 0 "^file,frame,.*,contacts,contact_precision," -- "${read_results[@]}" --csv "$tmp/contacts.h5"
check "bad check interval" 2 "expected every, off or a positive" -- "$cdbench" run --device cpu --quiet --check sometimes
check "several pipelines in one run" 0 "pipeline: c on cpu" -- "$cdbench" run --device cpu --quiet --frames 0:3 --pipeline bvh,static,c
check "several pipelines need a pattern" 2 "\\{pipeline\\}" -- "$cdbench" run --device cpu --quiet --pipeline bvh,c --out "$tmp/x.h5"
check "bad threshold order" 2 "threshold" -- "$cdbench" run --device cpu --quiet --pipeline c --threshold-refit 0.5 --threshold-build 0.1
check "scenes info" 0 "vertex motion mean" -- "$cdbench" scenes info funnel --set frames=3
check "scenes generate" 0 "wrote 2 frames" -- "$cdbench" scenes generate funnel --set frames=2 --out "$tmp/gen"
check "generated scene runs" 0 "frames 0:2" -- "$cdbench" run --device cpu --scene "$tmp/gen"
# Frames already in --out may be another scene's: replaced only with --overwrite, as run --out.
check "scenes generate over earlier frames refused" 2 "^cdbench: error: --out $tmp/gen: holds 2 frames an earlier generation wrote; pass --overwrite" -- \
  "$cdbench" scenes generate cloth-wave --set res=4 --set frames=3 --out "$tmp/gen"
[[ ! -e $tmp/gen/frame_0002.obj ]] && echo "ok   refused generation wrote nothing" || fail "refused generation wrote frames"
check "scenes generate --overwrite replaces them" 0 "wrote 3 frames of cloth-wave" -- \
  "$cdbench" scenes generate cloth-wave --set res=4 --set frames=3 --out "$tmp/gen" --overwrite
# A scene with declared queries: its objects and queries go into DIR/scene.json, which runs
# it with them (the same pairs by query as the scene itself); a scene without them, written
# over it, removes it.
check "scenes generate writes the queries' descriptor" 0 "wrote its objects and declared queries to $tmp/genq/scene.json" -- \
  "$cdbench" scenes generate cloth-ball-inter --set res=12 --set frames=3 --out "$tmp/genq"
direct=$("$cdbench" run --device cpu --quiet --scene cloth-ball-inter --set res=12 --set frames=3 2>&1 | grep -E "^  pairs ")
described=$("$cdbench" run --device cpu --quiet --scene "$tmp/genq/scene.json" 2>&1 | grep -E "^  pairs ")
[[ -n $direct && $described == "$direct" ]] && echo "ok   the descriptor runs the frames with their queries" ||
  fail "the descriptor's pairs: '$described', the scene's: '$direct'"
[[ $direct == *"(self "*", inter "* ]] && echo "ok   the scene's pairs are by query" || fail "no pairs by query: $direct"
check "generate over a descriptor refused" 2 "holds 3 frames and scene.json an earlier generation wrote" -- \
  "$cdbench" scenes generate cloth-wave --set res=4 --set frames=3 --out "$tmp/genq"
"$cdbench" scenes generate cloth-wave --set res=4 --set frames=3 --out "$tmp/genq" --overwrite >/dev/null
[[ ! -e $tmp/genq/scene.json ]] && echo "ok   a scene without queries removes the old descriptor" || fail "scene.json left"
mkdir -p "$tmp/own-scenes"
printf '{"generator": "funnel", "params": {"res": 4, "frames": 2}}' >"$tmp/own-scenes/tiny.json"
check "scenes info takes --scenes-dir after the scene" 0 "^scene +tiny" -- "$cdbench" scenes info tiny --scenes-dir "$tmp/own-scenes"
check "scenes list of a missing --scenes-dir refused" 2 "^cdbench: error: --scenes-dir $tmp/nonexistent: no such directory" -- \
  "$cdbench" scenes list --scenes-dir "$tmp/nonexistent"
check "scenes list of a missing CDBENCH_SCENES refused" 2 "^cdbench: error: CDBENCH_SCENES=$tmp/nonexistent: no such directory" -- \
  env CDBENCH_SCENES="$tmp/nonexistent" "$cdbench" scenes list
check "scenes list of a file refused" 2 "^cdbench: error: --scenes-dir $tmp/badq.json: not a directory" -- \
  "$cdbench" scenes list --scenes-dir "$tmp/badq.json"
check "scenes list takes --scenes-dir" 0 "^tiny +[0-9]+ triangles" -- "$cdbench" scenes list --scenes-dir "$tmp/own-scenes"
check "scenes generate takes --scenes-dir" 0 "wrote 2 frames of tiny" -- \
  "$cdbench" scenes generate tiny --scenes-dir "$tmp/own-scenes" --out "$tmp/gen-tiny"
check "scenes takes --scenes-dir before the subcommand too" 0 "^scene +tiny" -- "$cdbench" scenes --scenes-dir "$tmp/own-scenes" info tiny
# A results file a run is still writing holds HDF5's lock: said to be in use, not the
# system's "resource temporarily unavailable".
"$cdbench" run --device cpu --quiet --scene funnel --set res=8 --set frames=20 --repeat 100000 --out "$tmp/busy.h5" \
  >/dev/null 2>&1 &
busy_run=$!
for _ in $(seq 100); do [[ -s $tmp/busy.h5 ]] && break; sleep 0.1; done
check "report of a file a run is writing says it is in use" 1 "busy.h5: the file is in use by another process" -- \
  "$cdbench" report "$tmp/busy.h5"
kill "$busy_run"
wait "$busy_run" 2>/dev/null
check "unknown generator parameter lists the known" 2 "--set nope=1: generator 'funnel', parameter 'nope': unknown parameter \\(known: res, frames, warmup, substeps, seed, segments, ball_level, ball_speed\\)" -- "$cdbench" scenes info funnel --set nope=1
check "scenes info lists the parameters" 0 "^parameter +res +integer +16 \\(default 56\\) +range 2\\.\\.20000" -- "$cdbench" scenes info funnel --set res=16 --set frames=2
check "a count past its range is refused, not wrapped" 2 "--set res=4294967312: generator 'funnel', parameter 'res': 4294967312 is out of range: must be between 2 and 20000" -- "$cdbench" run --device cpu --scene funnel --set res=4294967312
check "frames past uint32 is refused, not wrapped" 2 "--set frames=4294967297: generator 'funnel', parameter 'frames': 4294967297 is out of range" -- "$cdbench" run --device cpu --scene funnel --set frames=4294967297
check "set on a mesh sequence" 2 "procedural" -- "$cdbench" scenes info "$tmp/gen" --set res=4

mkdir -p "$tmp/seq"
for f in 0 1; do
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 %d\nf 1 2 3\nf 1 2 4\n' "$f" >"$tmp/seq/frame_000$f.obj"
done
check "obj sequence runs" 0 "frames 0:2" -- "$cdbench" run --device cpu --scene "$tmp/seq"
check "obj sequence verifies" 0 "all pipelines match" -- "$cdbench" verify --device cpu --scene "$tmp/seq"

cp -r "$tmp/seq" "$tmp/nan"
printf 'v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n' >"$tmp/nan/frame_0001.obj"
check "NaN vertex names file, frame, vertex" 1 "frame_0001.obj: frame 1, vertex 2: non-finite" -- "$cdbench" run --device cpu --scene "$tmp/nan"

cp -r "$tmp/seq" "$tmp/count"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\nf 1 2 3\nf 1 2 4\nf 1 2 5\n' >"$tmp/count/frame_0001.obj"
check "changed topology names frame" 1 "frame_0001.obj: frame 1 has 3 triangles, frame 0 has 2" -- "$cdbench" run --device cpu --scene "$tmp/count"

mkdir -p "$tmp/bad"
printf 'this is not a mesh\n{{{\n' >"$tmp/bad/frame_0000.obj"
check "malformed OBJ names file" 1 "frame_0000.obj" -- "$cdbench" run --device cpu --scene "$tmp/bad"

mkdir -p "$tmp/empty"
check "empty directory" 1 "no .obj frames" -- "$cdbench" run --device cpu --scene "$tmp/empty"

printf '{"generator": "funnel", "params": {"res": 8, "frames": 3, "colour": 1}}' >"$tmp/typo.json"
check "unknown generator parameter" 1 "parameter 'colour': unknown parameter" -- "$cdbench" run --device cpu --scene "$tmp/typo.json"
printf '{"generator": "funnel", "extra": 1}' >"$tmp/key.json"
check "unknown descriptor key" 1 "/extra: unknown key" -- "$cdbench" run --device cpu --scene "$tmp/key.json"
printf '{"generator": ' >"$tmp/broken.json"
check "malformed JSON" 1 "broken.json: malformed JSON" -- "$cdbench" run --device cpu --scene "$tmp/broken.json"
printf '{"generator": "soup", "params": {"triangles": 0}}' >"$tmp/empty.json"
check "empty scene runs" 0 "pairs +0" -- "$cdbench" run --device cpu --scene "$tmp/empty.json"
printf '{"generator": "soup", "params": {"triangles": 1}}' >"$tmp/one.json"
check "one triangle verifies" 0 "all pipelines match" -- "$cdbench" verify --device cpu --scene "$tmp/one.json"

# Results files: complete, failed mid-run, interrupted; read back by the script and report.
out=$tmp/results
check "run writes a results file" 0 "results: $out/funnel.h5 \(20 frames\)" -- \
  "$cdbench" run --scene funnel --device cpu --quiet --out "$out/funnel.h5" --save-pairs
check "results file is complete" 0 "status: complete \(20 frames written\)" -- "${read_results[@]}" "$out/funnel.h5"
check "results file keeps pairs" 0 "pairs saved for 20 frames" -- "${read_results[@]}" --summary "$out/funnel.h5"
check "save-pairs needs --out" 2 "--save-pairs requires --out" -- "$cdbench" run --device cpu --save-pairs

mkdir -p "$tmp/midway"
for f in 0 1 2 3; do
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 %d\nf 1 2 3\nf 1 2 4\n' "$f" >"$tmp/midway/frame_000$f.obj"
done
printf 'v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n' >"$tmp/midway/frame_0002.obj"
check "a bad frame is found before the first is timed" 1 "frame_0002.obj: frame 2, vertex 2: non-finite" -- \
  "$cdbench" run --device cpu --scene "$tmp/midway" --out "$out/midway.h5"
if grep -q "^frame " "$tmp/out"; then fail "frames ran before the bad frame was found"; else echo "ok   no frame ran"; fi
[[ ! -e $out/midway.h5 ]] && echo "ok   no results file for a run that did not start" || fail "midway.h5 written"
mkdir -p "$tmp/natural"
for f in 0 1 2 10 11; do
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 %d\nf 1 2 3\nf 1 2 4\n' "$f" >"$tmp/natural/f$f.obj"
done
check "frames in natural order: f10 is frame 3" 0 "^frame +3 +box \[0 0 0\]\.\.\[1 1 10\]" -- "$cdbench" scenes info "$tmp/natural"
has "frames in natural order: f2 is frame 2" "$tmp/out" "^frame +2 +box \[0 0 0\]\.\.\[1 1 2\]"

# Interrupted: a scene far too long to finish, stopped by SIGTERM once it is under way.
printf '{"generator": "cloth-wave", "params": {"res": 16, "frames": 1000000}}' >"$tmp/endless.json"
"$cdbench" run --device cpu --scene "$tmp/endless.json" --out "$out/endless.h5" >"$tmp/endless.out" 2>&1 &
pid=$!
for _ in $(seq 600); do grep -q "^frame  *2 " "$tmp/endless.out" && break; sleep 0.1; done
kill -TERM "$pid"
wait "$pid"; rc=$?
if [[ $rc -eq 143 ]] && grep -q "interrupted by SIGTERM" "$tmp/endless.out"; then
  echo "ok   SIGTERM stops the run with 128+15"
else
  fail "SIGTERM stops the run: rc=$rc (want 143)"; tail -5 "$tmp/endless.out" | sed 's/^/    /'
fi
check "interrupted run leaves an incomplete file" 0 "error: interrupted by SIGTERM after [0-9]+ of 1000000 frames" -- \
  "${read_results[@]}" --summary "$out/endless.h5"

# Scene identity and options: a --set run carries its label, the report shows it, the
# options that differ between files, and the check columns when a file was checked.
check "run with --set writes a results file" 0 "results: " -- \
  "$cdbench" run --device cpu --quiet --scene funnel --set res=24 --frames 0:3 --front-cycle 2 --box-margin 0.5 --out "$out/funnel-res24.h5"
attrs() { "$python" -c "import h5py, json, sys; f = h5py.File(sys.argv[1]); print(json.dumps({k: (v.decode() if isinstance(v, bytes) else v.item() if hasattr(v, 'item') else v) for k, v in f.attrs.items()}, sort_keys=True)); print('groups', sorted(f.keys()))" "$1"; }
check "scene label attribute" 0 '"scene_label": "funnel\[res=24\]"' -- attrs "$out/funnel-res24.h5"
check "scene overrides attribute" 0 '"scene_overrides": "\{\\"res\\":24\}"' -- attrs "$out/funnel-res24.h5"
check "schema version 5" 0 '"schema_version": 5' -- attrs "$out/funnel-res24.h5"
cp "$out/funnel-res24.h5" "$tmp/future.h5"
"$python" -c "import h5py, sys; f = h5py.File(sys.argv[1], 'r+'); f.attrs['schema_version'] = 99; f.close()" "$tmp/future.h5"
check "report refuses a newer schema" 1 "future.h5: schema_version 99 is not one this cdbench reads \\(1 to 5\\)" -- "$cdbench" report "$tmp/future.h5"
check "no /quality group; pipeline c's plans; every pass; the memory peak" 0 "^groups \['frames', 'memory', 'passes', 'plans', 'summary'\]$" -- attrs "$out/funnel-res24.h5"
check "description of what ran" 0 '"scene_description": "funnel: .*\(funnel\[res=24\]\)"' -- attrs "$out/funnel-res24.h5"
check "numbers in params_json are numbers" 0 "^int int float str list \['res=24'\]$" -- "$python" -c "
import h5py, json, sys
o = json.loads(h5py.File(sys.argv[1]).attrs['params_json'])['options']
print(*(type(o[k]).__name__ for k in ('front-cycle', 'morton-bits', 'box-margin', 'frames', 'set')), o['set'])" "$out/funnel-res24.h5"
check "report shows the scene label" 0 "\| funnel\[res=24\] \| c \| cpu: [^|]* \| [0-9]+ \|" -- \
  "$cdbench" report "$out/funnel.h5" "$out/funnel-res24.h5"
check "report adds the options that differ" 0 "^\| file \| scene \| pipeline \| device \| triangles \| --box-margin \| --frames \| --front-cycle \| --save-pairs \| frames_run \|" -- \
  "$cdbench" report "$out/funnel.h5" "$out/funnel-res24.h5"
has "report's option values" "$tmp/out" "\| funnel\[res=24\] \| c \| [^|]* \| 3682 \| 0\.5 \| 0:3 \| 2 \| no \| 3 \|"
has "report's default option values" "$tmp/out" "funnel\.h5 \| funnel \| c \| [^|]* \| 8674 \| 0 \|  \| auto \| yes \| 20 \|"
check "report without differing options" 0 "^\| file \| scene \| pipeline \| device \| triangles \| frames_run \| mean_ms \|" -- \
  "$cdbench" report "$out/funnel.h5"
check "report shows check columns" 0 "\| recall_min \| precision_min \| contacts \| contact_precision \|" -- \
  "$cdbench" report "$tmp/contacts.h5" "$out/funnel.h5"
has "report's check values" "$tmp/out" "contacts\.h5 \|.*\| 1\.000000 \| (0\.99[0-9]+|1\.000000) \| [0-9]+ \| 0\.[0-9]+ \|"
check "report without checked files has no check columns" 0 "^\| file \| scene \| pipeline \| device \| triangles \| frames_run \| mean_ms \| noise_pct \| median_ms \| p95_ms \|" -- \
  "$cdbench" report "$out/funnel.h5"
# docs/results-format.md names exactly what a file holds.
"$cdbench" run --device cpu --quiet --frames 0:3 --check every --save-pairs --out "$out/documented.h5" >/dev/null 2>&1
check "results format documented exactly" 0 "^0 differences" -- \
  "$python" "$root/tests/cli/results_format_check.py" "$root/docs/results-format.md" "$out/documented.h5"
# --repeat stopped by SIGINT once passes have finished: they are kept, summed up and written.
"$cdbench" run --device cpu --scene funnel --frames 0:3 --repeat 1000000 --quiet --out "$out/repeat.h5" >"$tmp/repeat.out" 2>&1 &
pid=$!
for _ in $(seq 600); do grep -q "^copy bandwidth" "$tmp/repeat.out" && break; sleep 0.1; done
sleep 2
kill -INT "$pid"
wait "$pid"; rc=$?
if [[ $rc -eq 130 ]] && grep -qE "interrupted by SIGINT after [0-9]+ of 1000000 passes \(the finished passes kept\)" "$tmp/repeat.out" &&
   grep -qE "^  noise .* over [0-9]+ passes" "$tmp/repeat.out"; then
  echo "ok   SIGINT under --repeat keeps the finished passes"
else
  fail "SIGINT under --repeat: rc=$rc (want 130)"; tail -8 "$tmp/repeat.out" | sed 's/^/    /'
fi
check "the kept passes are in the results file" 0 "status: incomplete \(3 frames written\)" -- "${read_results[@]}" "$out/repeat.h5"

# Buffer growth: summed up after the run, never printed while frames run; --quiet leaves the count.
printf '{"generator": "soup", "params": {"triangles": 200, "size": 1, "frames": 2}}' >"$tmp/dense.json"
check "growth summed up after the run" 0 "^  grew +pairs [0-9]+ times?, [0-9]+ to [0-9]+$" -- "$cdbench" run --device cpu --scene "$tmp/dense.json" --pipeline bvh
if grep -q "^cdbench: grew" "$tmp/out"; then fail "growth printed while frames ran"; else echo "ok   no growth line during the frames"; fi
check "quiet keeps only the growth count" 0 "^  memory .* [1-9][0-9]* growths" -- "$cdbench" run --device cpu --scene "$tmp/dense.json" --pipeline bvh --quiet
if grep -q "grew" "$tmp/out"; then fail "--quiet still lists the growth"; else echo "ok   --quiet lists no growth"; fi

check "report shows the complete run" 0 "\| funnel \| c \| cpu: .* \| complete \|" -- \
  "$cdbench" report "$out/funnel.h5" "$out/endless.h5"
check "report shows the interrupted run as incomplete" 0 "\| endless \| c \|.*\| incomplete .*SIGTERM" -- \
  "$cdbench" report "$out/funnel.h5" "$out/endless.h5"
check "report as CSV" 0 "endless\.h5,endless,c,.*,incomplete: interrupted by SIGTERM after [0-9]+ of 1000000 frames$" -- \
  "$cdbench" report --csv "$out/funnel.h5" "$out/endless.h5"
check "report names an unreadable file" 1 "unreadable: .*seq/frame_0000.obj" -- \
  "$cdbench" report "$out/funnel.h5" "$tmp/seq/frame_0000.obj"

finish CLI
