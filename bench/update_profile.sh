#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle (.devbundle): where a front update frame's
# time goes. Pipelines b and c with every phase timed (--front-cycle 4, so every fourth frame
# updates) on the anchor analogues, one HDF5 file per scene and pipeline into
# $OUT/update-h5.tar.xz; then Nsight Compute over every kernel of the first frames of
# funnel and the 32K and 522K cloths (two update frames each) into $OUT/ncu-update-*.csv.
# bench/ncu_summary.py makes the kernel tables.
#   PROFILE_PIPES   pipelines of the timed runs (default b,c)
#   NCU_PIPE        the pipeline profiled (default c)
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
bin=$bundle/bin/cdbench
h5=$out/update-h5
mkdir -p "$h5"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/gpu.txt"
declare -A args=(
  [funnel]="--scene funnel"
  [wave128]="--scene cloth-wave"
  [wave512]="--scene cloth-wave --set res=512 --set frames=20"
  [spheres]="--scene n-body --set spheres=150 --set cones=0 --set frames=40"
  [sphere]="--scene sphere"
  [cloth-ball]="--scene cloth-ball"
)
for name in funnel wave128 wave512 spheres sphere cloth-ball; do
  echo "=== $name"
  # shellcheck disable=SC2086
  "$bin" run --device cuda ${args[$name]} --pipeline "${PROFILE_PIPES:-b,c}" --quiet --front-cycle 4 \
    --out "$h5/$name-{pipeline}.h5" 2>&1 | grep -E "^device|^pipeline:|per frame|  [a-z_0-9]+ +mean|error"
done | tee "$out/update-phases.log"
tar -C "$h5" -cJf "$out/update-h5.tar.xz" . && rm -rf "$h5"
metrics="smsp__thread_inst_executed_per_inst_executed.ratio,regex:smsp__average_warps_issue_stalled_.*_per_issue_active\.ratio"
for name in funnel wave128 wave512; do
  # shellcheck disable=SC2086
  ncu --clock-control none --csv --page details --section SpeedOfLight --section Occupancy \
    --section LaunchStats --section MemoryWorkloadAnalysis --metrics "$metrics" \
    "$bin" run --device cuda ${args[$name]} --pipeline "${NCU_PIPE:-c}" --quiet --front-cycle 4 \
    --frames 0:9 --cuda-graph off --out /tmp/ncu.h5 >"$out/ncu-update-$name.csv" 2>"$out/ncu-update-$name.err" ||
    tail -5 "$out/ncu-update-$name.err"
  xz -9 "$out/ncu-update-$name.csv"
done
