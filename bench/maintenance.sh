#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle (.devbundle: bin/cdbench and its libraries):
# the anchor analogues of docs/front-maintenance.md with pipelines a, b, c and the
# baselines, every frame's timings into one HDF5 file per scene and pipeline under
# $OUT/maintenance/NAME/, the printed summaries into $OUT/maintenance.log.
# BASE_BIN="NAME=PATH ..." runs other cdbench binaries on the same cells right after
# (before/after in one call, same GPU); CONTROL=1 also the head binary with --front-cycle 4;
# VARIANTS="NAME=FLAGS;NAME=FLAGS" also the head binary with each set of flags (its own tag).
# bench/maintenance_report.py makes the tables.
#
#   CELLS  which cells run (default: all): wave128 wave512 wave708 spheres sphere cloth-ball funnel
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
mkdir -p "$out/maintenance"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$out/maintenance/gpu.txt"

# One run: TAG BIN PIPELINES NAME SCENE ARGS...
one() {
  local tag=$1 bin=$2 p=$3 name=$4 scene=$5
  shift 5
  local dir=$out/maintenance/$tag
  mkdir -p "$dir"
  echo "=== $tag $name $p $*"
  "$bin" run --device cuda --scene "$scene" --pipeline "$p" --quiet --phase-timing off \
    --out "$dir/$name-{pipeline}.h5" "$@" 2>&1 |
    grep -E "^commit|^device|^scene|^pipeline:|per frame|error|Error"
}

# cell NAME SCENE PIPELINES ARGS...: the same frames with every binary, untimed phases,
# one pass (--repeat would average each frame over passes whose schedules differ under
# --front-cycle auto, hiding the update frames). CONTROL=1 adds the head binary with the
# fixed cycle of the base (--front-cycle 4) on a, b and c.
cell() {
  local name=$1 scene=$2 pipelines=$3
  shift 3
  one head "$bundle/bin/cdbench" "$pipelines" "$name" "$scene" "$@"
  for entry in ${BASE_BIN:-}; do
    one "${entry%%=*}" "${entry#*=}" "${BASE_PIPELINES:-$pipelines}" "$name" "$scene" "$@"
  done
  local variants=${VARIANTS:-} v
  while [[ -n $variants ]]; do
    v=${variants%%;*}
    [[ $variants == *";"* ]] && variants=${variants#*;} || variants=""
    # shellcheck disable=SC2086
    one "${v%%=*}" "$bundle/bin/cdbench" "${VARIANT_PIPELINES:-a,b,c}" "$name" "$scene" "$@" ${v#*=}
  done
  [[ ${CONTROL:-0} == 1 ]] && one head-cycle4 "$bundle/bin/cdbench" a,b,c "$name" "$scene" --front-cycle 4 "$@"
  return 0
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
