#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle (.devbundle: bin/cdbench and its libraries):
# the anchor analogues of docs/front-maintenance.md with pipelines a, b, c and the
# baselines, every frame's timings into one HDF5 file per scene and pipeline under
# $OUT/maintenance/NAME/, the printed summaries into $OUT/maintenance.log.
# BASE_BIN="NAME=PATH ..." runs other cdbench binaries on the same cells right after
# (before/after in one call, same GPU). scripts/maintenance_report.py makes the tables.
#
#   CELLS  which cells run (default: all): wave128 wave512 wave708 spheres sphere cloth-ball funnel
set -uo pipefail
bundle=${BUNDLE:-$PWD/.devbundle}
export LD_LIBRARY_PATH=$bundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export CDBENCH_SCENES=$PWD/scenes
out=${OUT:-/tmp/out}
mkdir -p "$out/maintenance"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$out/maintenance/gpu.txt"

# cell NAME SCENE PIPELINES ARGS...: the same frames with every binary, untimed phases.
cell() {
  local name=$1 scene=$2 pipelines=$3
  shift 3
  for entry in "head=$bundle/bin/cdbench" ${BASE_BIN:-}; do
    local tag=${entry%%=*} bin=${entry#*=}
    local dir=$out/maintenance/$tag
    mkdir -p "$dir"
    local p=$pipelines
    [[ $tag != head ]] && p=${BASE_PIPELINES:-$pipelines}
    echo "=== $tag $name $p $*"
    "$bin" run --device cuda --scene "$scene" --pipeline "$p" --quiet --phase-timing off --repeat 2 \
      --out "$dir/$name-{pipeline}.h5" "$@" 2>&1 |
      grep -E "^commit|^device|^scene|^pipeline:|per frame|mean|median|p95|error|Error"
  done
}

cells=${CELLS:-wave128 wave512 wave708 spheres sphere cloth-ball funnel}
{
  for c in $cells; do
    case $c in
      wave128) cell wave128 cloth-wave "${PIPES:-a,b,c,grid,hash,sweep,bvh}" ;;
      wave512) cell wave512 cloth-wave "${PIPES:-a,b,c,grid,hash,bvh}" --set res=512 --set frames=20 ;;
      wave708) cell wave708 cloth-wave "${PIPES:-a,b,c,grid,bvh}" --set res=708 --set frames=5 ;;
      spheres) cell spheres n-body "${PIPES:-a,b,c,grid,hash,sweep,bvh}" --set spheres=150 --set cones=0 --set frames=40 ;;
      sphere) cell sphere sphere "${PIPES:-a,b,c,grid,hash,sweep,bvh}" ;;
      cloth-ball) cell cloth-ball cloth-ball "${PIPES:-a,b,c,grid,hash,bvh}" ;;
      funnel) cell funnel funnel "${PIPES:-a,b,c,grid}" ;;
    esac
  done
} 2>&1 | tee "$out/maintenance.log"
tar -C "$out/maintenance" -cJf "$out/maintenance-h5.tar.xz" . && rm -rf "$out/maintenance"
