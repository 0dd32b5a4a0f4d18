#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle: the runs behind the GPU performance targets
# (docs/results.md, "Performance targets"), one HDF5 file per scene and pipeline under
# $OUT/targets, each run's summary in $OUT/targets.log; bench/perf_targets.py turns the
# files into the targets table. With BASE_BIN="NAME=PATH ..." (other cdbench binaries) every
# cell also runs with each of them, right after the first, into $OUT/NAME (A/B back to back
# on the same GPU).
#
#   TARGET_GROUPS  which groups run (default: all): steady cloth coherent nbody scaling
#   NCU=1          also profile the kernels behind each bottleneck into $OUT/ncu-*.csv
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
bin=$bundle/bin/cdbench
mkdir -p "$out/targets"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.mem --format=csv | tee "$out/gpu.txt"

# One run of several pipelines on the same frames; the summary lines go to the log.
cell() {
  local group=$1 scene=$2 pipelines=$3
  shift 3
  for entry in "targets=$bin" ${BASE_BIN:-}; do
    local dir=$out/${entry%%=*} b=${entry#*=}
    mkdir -p "$dir"
    echo "=== $group $scene $pipelines $* ($b)"
    "$b" run --device cuda --scene "$scene" --pipeline "$pipelines" --quiet \
      --out "$dir/$group-$(basename "$scene")-{pipeline}.h5" "$@" 2>&1 |
      grep -E "commit|^device|^scene|^pipeline:|per frame|syncs|floor|  [a-z_0-9]+ +mean|pairs |front |formula|memory|error"
  done
}

groups=${TARGET_GROUPS:-steady cloth coherent nbody scaling}
{
  for g in $groups; do
    case $g in
      # Funnel-size steady frames (graph replay of refit + preserve), pipelines a, b, c:
      # with every phase timed, and untimed (--phase-timing off: no event node between the
      # graph's kernels), the frame a simulator runs.
      steady)
        cell steady funnel a,b,c,unordered --repeat 3
        cell steady funnel-large a,b,c,unordered --repeat 3
        cell untimed funnel a,b,c,unordered --repeat 3 --phase-timing off
        cell untimed funnel-large a,b,c,unordered --repeat 3 --phase-timing off
        ;;
      # Cloth-ball: c against 0.3 ms; static against unordered; histogram against radix
      # sort on the same fronts; preserve against generate; every baseline; memory.
      cloth)
        cell cloth cloth-ball unordered,b,c,periodic,radix-order,bvh,grid,hash,sweep --repeat 3
        ;;
      # Other coherent cloths at ~100K and below: the fronts against the baselines.
      coherent)
        cell coherent cloth-100k unordered,b,c,periodic,radix-order,bvh,grid,hash --repeat 3
        cell coherent cloth-wave b,c,bvh,grid,hash --repeat 3
        cell coherent flag b,c,unordered,grid,hash --repeat 3
        ;;
      # Uniform many bodies, where the paper also found the grid methods competitive.
      nbody)
        cell nbody n-body b,c,unordered,bvh,grid,hash --frames 0:40 --repeat 2
        ;;
      # 10K to 10M triangles of one travelling-wave cloth: exponent and bandwidth floor.
      scaling)
        for res in 72 224 708 2236; do
          cell scaling "cloth-wave" b,c,bvh,grid --set res=$res --set frames=8 --repeat 2
          for f in "$out"/*/scaling-cloth-wave-*.h5; do
            [[ "$f" == *-res* ]] || mv "$f" "${f%.h5}-res$res.h5"
          done
        done
        ;;
    esac
  done
} 2>&1 | tee "$out/targets.log"

if [[ "${NCU:-0}" == 1 ]]; then
  # The kernels behind each bottleneck: their speed of light, occupancy, divergence and
  # why warps stall (bench/ncu_summary.py makes the tables).
  ncu_metrics="smsp__thread_inst_executed_per_inst_executed.ratio,regex:smsp__average_warps_issue_stalled_.*_per_issue_active\.ratio"
  profile() {
    local name=$1
    shift
    ncu --clock-control none --csv --page details --section SpeedOfLight --section Occupancy \
      --section LaunchStats --section MemoryWorkloadAnalysis --metrics "$ncu_metrics" \
      "$@" >"$out/ncu-$name.csv" 2>"$out/ncu-$name.err" || tail -5 "$out/ncu-$name.err"
  }
  profile cloth-ball-c -k regex:"for_each|one_block|tile" "$bin" run --device cuda --scene cloth-ball \
    --pipeline c --frames 0:9 --quiet --cuda-graph off
  profile funnel-c -k regex:"for_each|one_block|tile" "$bin" run --device cuda --scene funnel \
    --pipeline c --frames 0:6 --quiet --cuda-graph off
fi
# One compressed archive per binary (HDF5 compresses about 40 to 1), and the profiles
# compressed: the device tool brings back at most 8 files of at most 16 MiB each.
for e in "targets=" ${BASE_BIN:-}; do
  d=${e%%=*}
  tar -C "$out" -cJf "$out/h5-$d.tar.xz" "$d" && rm -rf "${out:?}/$d"
done
for f in "$out"/ncu-*.csv; do
  if [[ -f "$f" ]]; then xz -T0 "$f"; fi
done
