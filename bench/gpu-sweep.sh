#!/usr/bin/env bash
# The committed GPU sweep, end to end: the benchmark scenes x every pipeline and baseline
# (sweeps/h200-scenes.json) into DIR, the 2K-10M scaling series (sweeps/h200-scaling.json)
# into DIR/scaling, the operation micro-benchmarks (sweeps/h200-ops.json) into DIR/ops, then
# the generated report (scripts/make_report.sh) into DIR.
#
#   scripts/h200-sweep.sh DIR            # on a machine with the GPU
#   scripts/make_report.sh DIR DIR       # again, wherever h5py is, if the GPU machine has none
#
# Cells whose results are complete are skipped, so a re-run finishes an interrupted sweep.
set -euo pipefail
if [[ $# -ne 1 ]]; then
  echo "usage: scripts/h200-sweep.sh DIR" >&2
  exit 2
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
cdbench=${CDBENCH:-$here/cdbench}
dir=${1%/}
mkdir -p "$dir"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv >"$dir/gpu.txt" 2>/dev/null || true
"$cdbench" sweep "$root/sweeps/h200-scenes.json" --out "$dir" || true
"$cdbench" sweep "$root/sweeps/h200-scaling.json" --out "$dir/scaling" || true
"$cdbench" sweep "$root/sweeps/h200-ops.json" --out "$dir/ops" || true
if /usr/bin/python3 -c "import h5py, matplotlib, numpy" 2>/dev/null; then
  "$here/make_report.sh" "$dir" "$dir"
else
  echo "h5py/matplotlib not here: run scripts/make_report.sh $dir $dir where they are" >&2
fi
