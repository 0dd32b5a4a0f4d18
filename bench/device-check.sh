#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle (.devbundle/: bin/ and the libraries its binaries load):
# GPU tests, verify of every pipeline on the CUDA executor, and benchmarks. Logs go to $OUT.
# BENCH_SCENES / BENCH_PIPELINES choose the benchmark cells. GPU_TEST_FILTER chooses the GPU
# tests: all by default, the long ones (suite CudaLong, ctest bvh_cuda_long) included;
# -CudaLong.* runs what ctest's label gpu runs.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
bin=$bundle/bin
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.mem --format=csv | tee "$out/gpu.txt"
if [[ "${SKIP_TESTS:-0}" != 1 ]]; then
  echo "=== gpu tests"
  "$bin/test_bvh_cuda" --gtest_filter="${GPU_TEST_FILTER:-*}" 2>&1 | tee "$out/gpu-tests.log" | grep -E "^\[  (PASSED|FAILED|SKIPPED)|tests ran|Failure|FAILED"
fi
echo "=== verify"
for s in ${VERIFY_SCENES:-funnel cloth-wave random-100k}; do "$bin/cdbench" verify --device cuda --scene $s --brute-limit 200000 2>/dev/null | tail -10; done | tee "$out/verify.log"
echo "=== bench"
# All pipelines of a scene in one process, on the same frames (run --pipeline a,b,...); one
# HDF5 file per scene and pipeline, and the Markdown report generated from them.
pipelines=${BENCH_PIPELINES:-bvh,unordered,static,periodic,restructure,reference,a,b,c,radix-order,sweep,hash,grid}
mkdir -p "$out/h5"
for s in ${BENCH_SCENES:-cloth-100k}; do
  echo "--- $s"
  "$bin/cdbench" run --device cuda --scene $s --pipeline $pipelines --quiet --out "$out/h5/$s-{pipeline}.h5" 2>/dev/null |
    grep -E "commit|^scene|triangles|^pipeline:|first frame|per frame|  [a-z_0-9]+ +mean|pairs |front |formula|memory"
done 2>&1 | tee "$out/bench.log"
"$bin/cdbench" report "$out"/h5/*.h5 > "$out/report.md"
# One archive: the device tool brings back a limited number of files.
tar -C "$out" -cf "$out/h5.tar" h5 && rm -rf "$out/h5"
