#!/usr/bin/env bash
# The speed/accuracy knobs from the command line to the Pareto plot: tiny CPU runs of a
# fast-moving soup with each knob under --check every; the refit-every runs of tree
# pipelines must miss pairs (recall < 1, with the warning line), fat, swept and q16 boxes
# must not (recall 1, precision < 1); scripts/plot_pareto.py must draw them and tabulate them.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
hasnt() {  # hasnt NAME FILE PATTERN: no line of FILE matches PATTERN
  if grep -qE -- "$3" "$2"; then fail "$1: '$3' in $2"; else echo "ok   $1"; fi
}

export OMP_NUM_THREADS=1
res=$tmp/results
# Jitter larger than the triangles: the pairs change every frame.
printf '{"generator": "soup", "params": {"triangles": 800, "distribution": "clustered", "jitter": 3.0, "frames": 6, "seed": 5}}' \
  >"$tmp/soup-fast.json"
n=0
run() {  # run NAME ARGS...: one checked run into $res/NAME.h5, its output in $tmp/NAME.out
  local name=$1; shift
  "$cdbench" run --device cpu --quiet --scene "$tmp/soup-fast.json" --check every --out "$res/$name.h5" "$@" \
    >"$tmp/$name.out" 2>&1 || { cat "$tmp/$name.out"; fail "cdbench run $*"; }
  n=$((n + 1))
}
run bvh-plain --pipeline bvh
run bvh-margin --pipeline bvh --box-margin 0.002
run bvh-swept --pipeline bvh --boxes swept
run bvh-lazy --pipeline bvh --refit-every 3
run b-lazy --pipeline b --refit-every 3
run grid-lazy --pipeline grid --refit-every 3
run grid-margin --pipeline grid --box-margin 0.002
run bvh-q16 --pipeline bvh --box-precision q16
run grid-q16 --pipeline grid --box-precision q16

recall='recall min ([0-9.]+)'
has "lazy bvh misses pairs" "$tmp/bvh-lazy.out" "check .*recall min 0\.[0-9]+, "
has "lazy bvh warns with the measured recall" "$tmp/bvh-lazy.out" \
  "^  warning .*--refit-every 3 .*NOT conservative.*measured recall min 0\.[0-9]+ over 6 checked frames"
has "lazy b misses pairs" "$tmp/b-lazy.out" "check .*recall min 0\.[0-9]+, "
for name in bvh-margin bvh-swept grid-margin bvh-q16 grid-q16; do
  has "$name keeps recall 1" "$tmp/$name.out" "check .*recall min 1\.000000, precision min 0\.[0-9]+"
  hasnt "$name does not warn of lost pairs" "$tmp/$name.out" "warning .*NOT conservative|warning: float spacing"
done
has "grid ignores --refit-every" "$tmp/grid-lazy.out" "check .*recall min 1\.000000, precision min 1\.000000"
hasnt "grid ignores --refit-every: no warning of lost pairs" "$tmp/grid-lazy.out" "warning .*NOT conservative|warning: float spacing"
check "config records the knobs, not conservative" 0 '"boxes": "discrete".*"conservative": false.*"refit_every": 3' -- \
  "$python" -c "import h5py, json; print(json.dumps(json.loads(h5py.File('$res/bvh-lazy.h5')['/'].attrs['params_json'])['pipeline_config'], sort_keys=True))"
check "config records swept boxes" 0 '"boxes": "swept".*"conservative": true' -- \
  "$python" -c "import h5py, json; print(json.dumps(json.loads(h5py.File('$res/bvh-swept.h5')['/'].attrs['params_json'])['pipeline_config'], sort_keys=True))"
check "config records q16 boxes" 0 '"box_precision": "q16".*"conservative": true' -- \
  "$python" -c "import h5py, json; print(json.dumps(json.loads(h5py.File('$res/bvh-q16.h5')['/'].attrs['params_json'])['pipeline_config'], sort_keys=True))"
check "config records fp32 boxes by default" 0 '"box_precision": "fp32"' -- \
  "$python" -c "import h5py, json; print(json.dumps(json.loads(h5py.File('$res/bvh-plain.h5')['/'].attrs['params_json'])['pipeline_config'], sort_keys=True))"
check "q16 verifies exactly against the brute-force oracle on q16 boxes" 0 "all pipelines match the oracle" -- \
  "$cdbench" verify --device cpu --scene "$tmp/soup-fast.json" --frames 0:3 --pipelines bvh b sweep hash grid --box-precision q16
check "q16 verify refuses the discrete sweep oracle" 2 "--box-precision q16 needs the brute-force oracle" -- \
  "$cdbench" verify --device cpu --scene "$tmp/soup-fast.json" --frames 0:1 --brute-limit 10 --box-precision q16
check "unknown box precision refused" 2 "--box-precision: fp16 not in" -- \
  "$cdbench" run --device cpu --scene "$tmp/soup-fast.json" --box-precision fp16
check "negative margin refused" 2 "--box-margin" -- "$cdbench" run --device cpu --scene "$tmp/soup-fast.json" --box-margin -1
check "unknown box kind refused" 2 "--boxes" -- "$cdbench" run --device cpu --scene "$tmp/soup-fast.json" --boxes fat

check "plot_pareto draws the runs" 0 "^\| pipeline \| box margin" -- \
  "$python" "$root/scripts/plot_pareto.py" "$res" --scene soup-fast --out "$tmp/pareto.png" --table
cp "$tmp/out" "$tmp/table.md"
has "Pareto points are labelled with their margin" "$tmp/table.md" \
  "^wrote .*Pareto front, its points labelled with their margin: [a-z ]+ [1-9][0-9]* \(margins [0-9.e+-]+(, [0-9.e+-]+)*\); "
if [[ "$(head -c 8 "$tmp/pareto.png" 2>/dev/null | od -An -tx1 | tr -d ' \n')" == 89504e470d0a1a0a ]]; then
  echo "ok   pareto.png is a PNG"
else
  fail "pareto.png missing or not a PNG"
fi
rows=$(grep -cE '^\| (bvh|b|grid) \|' "$tmp/table.md")
[[ $rows -eq $n ]] && echo "ok   one table row per run" || fail "table has $rows rows, want $n"
num='[0-9.]+'
has "row: plain bvh exact" "$tmp/table.md" "^\| bvh \| 0 \| discrete \| fp32 \| 1 \| yes \| $num \| 1\.000000 \| 1\.000000 \| 1\.000000 \| $num \|"
has "row: bvh margin" "$tmp/table.md" "^\| bvh \| 0\.002 \| discrete \| fp32 \| 1 \| yes \| $num \| 1\.000000 \| 0\.[0-9]+ \| 0\.[0-9]+ \| $num \|"
has "row: bvh swept" "$tmp/table.md" "^\| bvh \| 0 \| swept \| fp32 \| 1 \| yes \| $num \| 1\.000000 \| 0\.[0-9]+ \| 0\.[0-9]+ \| $num \|"
has "row: bvh lazy" "$tmp/table.md" "^\| bvh \| 0 \| discrete \| fp32 \| 3 \| \*\*no\*\* \| $num \| 0\.[0-9]+ \|"
has "row: b lazy" "$tmp/table.md" "^\| b \| 0 \| discrete \| fp32 \| 3 \| \*\*no\*\* \| $num \| 0\.[0-9]+ \|"
has "row: grid lazy is exact" "$tmp/table.md" "^\| grid \| 0 \| discrete \| fp32 \| 3 \| yes \| $num \| 1\.000000 \| 1\.000000 \|"
has "row: bvh q16" "$tmp/table.md" "^\| bvh \| 0 \| discrete \| q16 \| 1 \| yes \| $num \| 1\.000000 \| 0\.[0-9]+ \| 0\.[0-9]+ \| $num \|"
# The fastest run of recall 1 is always on the recall front, whatever the timings.
has "a conservative run is on the recall front" "$tmp/table.md" "^\| [a-z]+ \| [0-9.]+ \| [a-z]+ \| [a-z0-9]+ \| [0-9]+ \| yes \| $num \| 1\.000000 \| .*\| recall"

"$cdbench" run --device cpu --quiet --scene "$tmp/soup-fast.json" --pipeline bvh --out "$tmp/unchecked/bvh.h5" >/dev/null 2>&1
check "unchecked runs are left out, named" 1 "bvh.h5: no frame checked" -- \
  "$python" "$root/scripts/plot_pareto.py" "$tmp/unchecked" --out "$tmp/x.png"

finish pareto
