#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle (.devbundle: bin/cdbench and its libraries):
# --box-precision fp32 against fp64 (and q16) per pipeline, docs/design.md "Box precision".
#   1. cost: cloth-ball and a 1M-triangle cloth, every pipeline with fp32 then fp64 on the
#      same frames in one process each, --repeat 3, phases untimed;
#   2. accuracy: cloth-ball and n-body with every frame checked against the double oracle
#      (fp32, fp64, q16), and cloth-ball moved by 1e5 (float spacing 0.4 of its median edge
#      there; further out fp32 merges it into billions of pairs), for the Pareto points.
# Results: $OUT/precision-h5.tar.xz (one HDF5 file per cell), $OUT/precision.log.
# bench/precision_report.py makes the tables.
#
#   CELLS  which cells run (default: all): cost-ball cost-1m check-ball check-ball-far check-nbody
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
mkdir -p "$out/precision"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$out/precision/gpu.txt"
bin=$bundle/bin/cdbench

# run NAME PRECISION PIPELINES SCENE ARGS...
run() {
  local name=$1 precision=$2 p=$3 scene=$4
  shift 4
  echo "=== $name $precision $p $*"
  "$bin" run --device cuda --scene "$scene" --pipeline "$p" --quiet --box-precision "$precision" \
    --out "$out/precision/$name-$precision-{pipeline}.h5" "$@" 2>&1 |
    grep -E "^commit|^device|^scene|^pipeline:|^warning|per frame|check |error|Error"
}

all=a,b,c,bvh,grid,hash,sweep
cells=${CELLS:-cost-ball cost-1m check-ball check-ball-far check-nbody}
{
  for c in $cells; do
    case $c in
      # Two rounds of fp32 then fp64: the order's effect shows between the rounds.
      cost-ball)
        for r in 1 2; do for p in fp32 fp64; do
          run "cost-ball-$r" "$p" "$all" cloth-ball --repeat 3 --phase-timing off
        done; done ;;
      cost-1m)
        for r in 1 2; do for p in fp32 fp64; do
          run "cost-1m-$r" "$p" a,b,c,bvh,grid cloth-wave --set res=708 --set frames=5 --repeat 3 --phase-timing off
        done; done ;;
      check-ball)
        for p in fp32 fp64 q16; do run check-ball "$p" b,c,grid,hash cloth-ball --frames 40:46 --check every; done ;;
      check-ball-far)
        for p in fp32 fp64; do
          run check-ball-far "$p" c,grid cloth-ball --frames 40:46 --check every --set placement.offset=1e5
        done ;;
      check-nbody)
        for p in fp32 fp64 q16; do run check-nbody "$p" c,grid,hash n-body --frames 0:6 --check every; done ;;
    esac
  done
} 2>&1 | tee "$out/precision.log"
tar -C "$out/precision" -cJf "$out/precision-h5.tar.xz" . && rm -rf "$out/precision"
