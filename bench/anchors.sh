#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle: the analogues of the bar's scenes
# (docs/results.md "Against the strongest peer"). Each scene is generated once as OBJ frames,
# so a second binary without its generator runs the very same frames; then, per scene:
# c, a, b, grid and bvh as the bar measured them (--phase-timing off --repeat 2), c once
# more in a single pass (its p95 without averaging), and c with --rebuild-degraded off.
# With BASE_BIN="NAME=PATH ..." each other binary runs c (both ways) right after, on the
# same GPU. Files: $OUT/anchors/BINARY/MODE-SCENE-PIPELINE.h5; bench/anchors_report.py
# makes the tables.
#
#   ANCHOR_SCENES  scenes to run (default: all seven below)
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
bin=$bundle/bin/cdbench
archive=$out/anchors-h5.tar.xz
out=$out/anchors
frames=${FRAMES_DIR:-/tmp/anchor-frames}
mkdir -p "$out" "$frames"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv | tee "$out/gpu.txt"
scenes=${ANCHOR_SCENES:-cloth-wave spheres cloth-wave-522k cloth-wave-1m crumple garment funnel}

run() {
  local b=$1 dir=$2 mode=$3 scene=$4 pipelines=$5
  shift 5
  mkdir -p "$dir"
  echo "=== $mode $scene $pipelines $* ($b)"
  "$b" run --device cuda --scene "$frames/$scene" --pipeline "$pipelines" --quiet --phase-timing off \
    --out "$dir/$mode-$scene-{pipeline}.h5" "$@" 2>&1 |
    grep -E "commit|^device|^pipeline:|per frame|  total +mean|pairs |memory|error"
}

{
  for s in $scenes; do
    [[ -d "$frames/$s" ]] || "$bin" scenes generate "$s" --out "$frames/$s" > /dev/null || continue
    run "$bin" "$out/new" repeat "$s" c,a,b,grid,bvh --repeat 2
    run "$bin" "$out/new" single "$s" c
    run "$bin" "$out/new" keep-tree "$s" c --repeat 2 --rebuild-degraded off
    for entry in ${BASE_BIN:-}; do
      run "${entry#*=}" "$out/${entry%%=*}" repeat "$s" c --repeat 2
      run "${entry#*=}" "$out/${entry%%=*}" single "$s" c
    done
    # One archive, refreshed after each scene: the device tool brings back only a few files,
    # and what a cut-short call finished still comes back.
    tar -C "$out" -cJf "$archive" .
  done
} 2>&1 | tee "$out/anchors.log"
tar -C "$out" -cJf "$archive" . && rm -rf "$out"
