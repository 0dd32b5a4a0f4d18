#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle (.devbundle, see ../shared/tools/device-bundle):
# GPU tests, verify on the CUDA executor, and the foundation benchmarks. Logs go to $OUT.
set -uo pipefail
export LD_LIBRARY_PATH=$PWD/.devbundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export CDBENCH_SCENES=$PWD/scenes
bin=$PWD/.devbundle/bin
out=${OUT:-/tmp/out}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.mem --format=csv | tee "$out/gpu.txt"
step() { echo "=== $*"; }
if [[ "${SKIP_TESTS:-0}" != 1 ]]; then
  step gpu tests
  "$bin/test_bvh_cuda" 2>&1 | tee "$out/gpu-tests.log" | grep -E "PASSED|FAILED|SKIPPED|tests ran" 
fi
step verify
for s in funnel cloth-wave; do "$bin/cdbench" verify --device cuda --scene $s 2>&1 | tail -4; done | tee "$out/verify.log"
"$bin/cdbench" verify --device cuda --scene random-100k --brute-limit 200000 2>&1 | tail -4 | tee -a "$out/verify.log"
step bench
for s in cloth-wave random-100k random-1m random-10m; do
  for p in bvh reference; do
    echo "--- $s $p"
    "$bin/cdbench" run --device cuda --scene $s --pipeline $p --quiet 2>&1 | grep -E "first frame|per frame|build |order |refit |query |pairs |memory"
  done
done 2>&1 | tee "$out/bench.log"
echo "--- random-100k brute (oracle), 2 frames"
"$bin/cdbench" run --device cuda --scene random-100k --pipeline brute --frames 0:2 --warmup 0 --quiet 2>&1 | grep -E "per frame|query |pairs " | tee -a "$out/bench.log"
echo "--- random-1m brute (oracle), 1 frame"
timeout 100 "$bin/cdbench" run --device cuda --scene random-1m --pipeline brute --frames 0:1 --warmup 0 --quiet 2>&1 | grep -E "per frame|query |pairs " | tee -a "$out/bench.log"
