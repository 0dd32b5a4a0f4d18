#!/usr/bin/env bash
# The library on the GPU machine (docs/library.md "On the GPU machine"), from the repository
# root, with an installed package built with CUDA elsewhere and carried here:
#   PREFIX=<install prefix> OUT=<dir> [CDBENCH=<cdbench binary>] bash bench/api_check.sh
# 1. examples/ built against PREFIX alone; cloth_loop with the cuda executor for pipelines c,
#    b, bvh and grid, every frame equal to the oracle;
# 2. the API's overhead per frame (api_frames, cloth-wave 128x128): c on cuda, over the
#    scene's 60 frames and over 600 (its motion slowed to span them), and c on cpu for reference;
# 3. with CDBENCH, the same scene through the CLI:
#    cdbench run --device cuda --scene cloth-wave --pipeline c --phase-timing off --repeat 3,
#    whose pairs must be api_frames' on every frame;
# 4. python/ built on its own against PREFIX for this machine's Python (PYTHON, default
#    python3; pybind11 from `PYTHON -m pybind11 --cmakedir`), then tests/python/check_cuda.py
#    (device arrays passed in place: CuPy, PyTorch, Numba, raw) and tests/python/test_cdbench.py.
# Everything goes to $OUT/api_check.log, each step ending in a PASS or FAIL line, then a
# summary; the exit status is 1 if any step failed. EXECUTOR=cpu runs every step on the host
# executor instead (no GPU needed: how the script itself is tested, tests/cli/install_tests.sh).
# JOBS: build parallelism (default 8); LONG_FRAMES: the longer overhead run's frames (600).
set -uo pipefail
if [[ -z ${PREFIX:-} || -z ${OUT:-} ]]; then
  echo "usage: PREFIX=<cdbench install prefix> OUT=<output dir> [CDBENCH=<cdbench>] bash bench/api_check.sh" >&2
  exit 2
fi
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
prefix=$(cd "$PREFIX" && pwd) || exit 2
executor=${EXECUTOR:-cuda}
python=${PYTHON:-python3}
jobs=${JOBS:-8}
long_frames=${LONG_FRAMES:-600}
mkdir -p "$OUT" || exit 2
out=$(cd "$OUT" && pwd)
log=$out/api_check.log
: >"$log"
passed=() failed=()

say() { printf '%s\n' "$*" | tee -a "$log"; }
pass() { passed+=("$1"); say "PASS $1"; }
fail() { failed+=("$1"); say "FAIL $1"; }
# step NAME PATTERN COMMAND...: runs COMMAND, its output into the log (and into $out/NAME.txt,
# for the summary); PASS when it exits 0 and its output has PATTERN (empty: anything).
step() {
  local name=$1 pattern=$2
  shift 2
  say "=== $name: $*"
  "$@" >"$out/$name.txt" 2>&1
  local rc=$?
  cat "$out/$name.txt" >>"$log"
  if ((rc == 0)) && { [[ -z $pattern ]] || grep -q -- "$pattern" "$out/$name.txt"; }; then
    pass "$name"
  else
    tail -n 8 "$out/$name.txt" | sed 's/^/    /'
    fail "$name (exit $rc)"
  fi
}

say "api_check: $(date -u '+%Y-%m-%d %H:%M:%S UTC'), executor $executor"
say "repository: $root (commit $(git -C "$root" rev-parse --short=12 HEAD 2>/dev/null || echo unknown))"
say "package: $prefix"
{
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
  cmake --version | head -1
  c++ --version | head -1
  [[ -x /usr/local/cuda/bin/nvcc ]] && /usr/local/cuda/bin/nvcc --version | tail -1
  "$python" --version
} 2>&1 | sed 's/^/  /' | tee -a "$log"

config=$prefix/lib/cmake/cdbench/cdbenchConfig.cmake
if [[ ! -f $config ]]; then
  fail "package: no $config"
elif [[ $executor == cuda ]] && ! grep -q '^set(cdbench_CUDA ON)' "$config"; then
  fail "package: built without CUDA (cdbench_CUDA is not ON in $config)"
else
  pass "package: $config"
fi

generator=()
command -v ninja >/dev/null && generator=(-G Ninja)

# 1. examples/ against the package, the loop on every frame against the oracle.
build_examples() {
  cmake -S "$root/examples" -B "$out/build-examples" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" && cmake --build "$out/build-examples" -j "$jobs"
}
step examples-build "" build_examples
examples=$out/build-examples
for pipeline in c b bvh grid; do
  step "cloth_loop-$pipeline" "every frame equals the oracle" "$examples/cloth_loop" "$pipeline" "$executor" 60
done

# 2. The API's overhead, and the CPU executor's for reference.
step "api_frames-c-$executor-60" "PASS" "$examples/api_frames" c "$executor" 60 5
# The longer run's warm-up: a tenth of it, at least the scene run's 5 frames.
long_warmup=$((long_frames / 10 > 5 ? long_frames / 10 : 5))
step "api_frames-c-$executor-$long_frames" "PASS" "$examples/api_frames" c "$executor" "$long_frames" "$long_warmup"
[[ $executor == cpu ]] || step api_frames-c-cpu-60 "PASS" "$examples/api_frames" c cpu 60 5

# 3. The CLI on the same scene, its libraries next to it where it came in a bundle (bin/, lib/).
if [[ -n ${CDBENCH:-} ]]; then
  cli_lib=$(cd "$(dirname "$CDBENCH")/.." && pwd)/lib
  [[ -d $cli_lib ]] && export LD_LIBRARY_PATH=$cli_lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  CDBENCH_SCENES=$root/scenes step "cli-c-$executor" "" "$CDBENCH" run --device "$executor" --scene cloth-wave \
    --pipeline c --phase-timing off --repeat 3
  # The same frames: the CLI's pair count and the API's, frame by frame.
  pairs_by_frame() { awk '$1 == "frame" { for (i = 2; i < NF; ++i) if ($i == "pairs") { print $2, $(i + 1); break } }' "$1"; }
  same_pairs() {
    diff <(pairs_by_frame "$out/cli-c-$executor.txt") <(pairs_by_frame "$out/api_frames-c-$executor-60.txt") &&
      echo "$(pairs_by_frame "$out/cli-c-$executor.txt" | wc -l) frames, the same pairs"
  }
  step "cli-api-same-pairs" "the same pairs" same_pairs
else
  say "(no CDBENCH given: the CLI's run of the scene left out)"
fi

# 4. The Python module for this machine's Python, and its checks.
build_python() {
  local pybind11_dir
  pybind11_dir=$("$python" -m pybind11 --cmakedir 2>/dev/null)
  cmake -S "$root/python" -B "$out/build-python" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DPython_EXECUTABLE="$(command -v "$python")" \
    ${pybind11_dir:+-Dpybind11_DIR="$pybind11_dir"} && cmake --build "$out/build-python" -j "$jobs"
}
step python-build "" build_python
step "python-check-$executor" "check_cuda: PASS" env PYTHONPATH="$out/build-python" "$python" \
  "$root/tests/python/check_cuda.py" --executor "$executor"
python_tests() { (cd "$root/tests/python" && PYTHONPATH=$out/build-python "$python" -m unittest -v test_cdbench); }
step python-tests "" python_tests

say ""
say "=== summary ($executor)"
for f in "$out"/api_frames-*.txt; do
  [[ -f $f ]] || continue
  say "$(basename "$f" .txt):"
  grep -E '^  (wall|api|overhead|pairs|measured) ' "$f" | tee -a "$log"
done
if [[ -f $out/cli-c-$executor.txt ]]; then
  say "cli-c-$executor:"
  sed -n '/^summary:/,/^  pairs /p' "$out/cli-c-$executor.txt" | grep -E '^summary|^  (first frame|per frame|noise|upload|pairs) ' |
    sed 's/^/  /' | tee -a "$log"
fi
grep -h "^PASS \|^FAIL " "$out/python-check-$executor.txt" 2>/dev/null | sed 's/^/  python: /' | tee -a "$log"
say "api_check: ${#passed[@]} passed, ${#failed[@]} failed"
for f in "${failed[@]}"; do say "  failed: $f"; done
((${#failed[@]} == 0))
