#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle (.devbundle: bin/cdbench and its libraries):
# every pipeline but the brute-force oracle on funnel, cloth-ball, cloth-100k and n-body,
# with the bundle's cdbench and with each binary of BASE_BIN="NAME=PATH ...", scene by
# scene back to back (same GPU, same frames), --repeat 3, phases untimed, a fixed
# --front-cycle 4 so that both binaries maintain their fronts on the same frames. One HDF5
# file per binary, scene and pipeline under $OUT/ab/NAME/; the summaries in $OUT/ab.log.
# bench/maintenance_report.py $OUT/ab/* makes the table.
#
#   SCENES     (default: funnel cloth-ball cloth-100k n-body)
#   PIPELINES  (default: every pipeline but brute)
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
mkdir -p "$out/ab"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$out/ab/gpu.txt"
pipelines=${PIPELINES:-bvh,unordered,static,periodic,restructure,reference,a,b,c,radix-order,sweep,hash,grid}
{
  for scene in ${SCENES:-funnel cloth-ball cloth-100k n-body}; do
    for entry in "head=$bundle/bin/cdbench" ${BASE_BIN:-}; do
      tag=${entry%%=*}
      mkdir -p "$out/ab/$tag"
      echo "=== $tag $scene"
      "${entry#*=}" run --device cuda --scene "$scene" --pipeline "$pipelines" --quiet --phase-timing off \
        --repeat 3 --front-cycle 4 --out "$out/ab/$tag/$scene-{pipeline}.h5" 2>&1 |
        grep -E "^commit|^pipeline:|per frame|error|Error"
    done
  done
} 2>&1 | tee "$out/ab.log"
tar -C "$out/ab" -cJf "$out/ab-h5.tar.xz" . && rm -rf "$out/ab"
