#!/usr/bin/env bash
# The committed GPU sweep, end to end: the benchmark scenes x every pipeline and baseline
# (sweeps/gpu-scenes.json) into DIR, the 2K-10M scaling series (sweeps/gpu-scaling.json)
# into DIR/scaling, the operation micro-benchmarks (sweeps/gpu-ops.json) into DIR/ops, then
# the generated report (scripts/make_report.sh) into DIR.
#
#   bench/gpu-sweep.sh DIR             # on a machine with the GPU
#   scripts/make_report.sh DIR DIR     # again, wherever h5py is, if the GPU machine has none
#
# Cells whose results are complete are skipped, so a re-run finishes an interrupted sweep.
set -euo pipefail
if [[ $# -ne 1 ]]; then
  echo "usage: bench/gpu-sweep.sh DIR" >&2
  exit 2
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
cdbench=${CDBENCH:-$root/scripts/cdbench}
dir=${1%/}
mkdir -p "$dir"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv >"$dir/gpu.txt" 2>/dev/null || true
"$cdbench" sweep "$root/sweeps/gpu-scenes.json" --out "$dir" || true
"$cdbench" sweep "$root/sweeps/gpu-scaling.json" --out "$dir/scaling" || true
"$cdbench" sweep "$root/sweeps/gpu-ops.json" --out "$dir/ops" || true
if /usr/bin/python3 -c "import h5py, matplotlib, numpy" 2>/dev/null; then
  "$root/scripts/make_report.sh" "$dir" "$dir"
else
  echo "h5py/matplotlib not here: run scripts/make_report.sh $dir $dir where they are" >&2
fi
