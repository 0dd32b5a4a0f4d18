#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle: the bar's scenes (the cross-system
# comparison's analogues, bench/bar_report.py's PEER_MS: cloth-wave, spheres,
# cloth-wave-522k, cloth-wave-1m, crumple, garment; garment-avatar, the garment with its
# avatar, with its declared queries) and the paper's six benchmarks (flag, funnel-large,
# cloth-ball, flamenco, n-body, dragon) with the funnel, each generated once as OBJ frames so
# that every binary runs the very same frames.
# One untimed process of the new binary on the funnel first. Per scene, in one process
# each: the new binary's c, b, a, grid and hash, then each base
# binary's c and b (BASE_BIN="NAME=PATH ..."), `--repeat 3 --phase-timing off`, the default
# warm-up; the order of new and base alternates from scene to scene. BAR_10M=1 adds the 10M
# cloth wave, generated in memory by each process (`--scene cloth-wave --set res=2237`).
# Files: $OUT/bar/BINARY/SCENE-PIPELINE.h5 and bar.log in $OUT/bar-h5.tar.xz, refreshed
# after each scene (what a cut-short call finished still comes back);
# bench/bar_report.py makes the tables.
#
#   CDBENCH      the new binary (default: the bundle's bin/cdbench)
#   BAR_SCENES   scenes to run (default: the fourteen above)
#   BAR_CAP      seconds after which no further scene starts (default 540)
#   NEW_ARGS     options given to the new binary alone (ones the base binaries lack), e.g.
#                "--update-ahead on"; the report's log names them
#   SCENE_DATA   directory holding BCN_Epileptic.X and cgal-data.tar.gz, for machines
#                without assimp-testmodels and libcgal-demo (flamenco, garment, dragon)
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
bin=${CDBENCH:-$bundle/bin/cdbench}
archive=$out/bar-h5.tar.xz
out=$out/bar
frames=${FRAMES_DIR:-/tmp/bar-frames}
cap=${BAR_CAP:-540}
mkdir -p "$out/new" "$frames"
start=$(date +%s)
scenes=${BAR_SCENES:-cloth-wave spheres cloth-wave-522k cloth-wave-1m crumple garment garment-avatar flag funnel-large cloth-ball flamenco n-body dragon funnel}

generate_args() {
  local data=${SCENE_DATA:-}
  [[ -n "$data" ]] || return 0
  case $1 in
    dragon) echo "--set scan=$data/cgal-data.tar.gz" ;;
    flamenco | garment | garment-avatar) echo "--set body=$data/BCN_Epileptic.X" ;;
  esac
}

run() {
  local b=$1 dir=$2 scene=$3 name=$4 pipelines=$5
  shift 5
  mkdir -p "$dir"
  echo "=== $name $pipelines ($b) at $(($(date +%s) - start)) s"
  "$b" run --device cuda --scene "$scene" --pipeline "$pipelines" --quiet --phase-timing off --repeat 3 \
    --out "$dir/$name-{pipeline}.h5" "$@" 2>&1 |
    grep -E "commit|^device|^pipeline:|per frame|pairs |memory|error"
}

each_binary() {
  local index=$1 scene=$2 name=$3
  shift 3
  local order=(new ${BASE_BIN:-})
  if (( index % 2 == 1 )); then order=(${BASE_BIN:-} new); fi
  for entry in "${order[@]}"; do
    if [[ $entry == new ]]; then
      # shellcheck disable=SC2086
      run "$bin" "$out/new" "$scene" "$name" c,b,a,grid,hash "$@" ${NEW_ARGS:-}
    else
      run "${entry#*=}" "$out/${entry%%=*}" "$scene" "$name" c,b "$@"
    fi
  done
}

# What `run --scene` is given for scene $1: its frames, or the descriptor `scenes generate`
# wrote beside them where the scene declares queries (garment-avatar), which restores its
# objects and queries (OBJ frames keep neither).
scene_of() {
  if [[ -f "$frames/$1/scene.json" ]]; then echo "$frames/$1/scene.json"; else echo "$frames/$1"; fi
}

{
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.mem,temperature.gpu --format=csv
  "$bin" --version | head -3
  echo "new binary's options: ${NEW_ARGS:-none}"
  # One untimed process first: the bar's first process ran its equal-plan frames 1.21-1.24x
  # slower than the same binary's later process on the same frames (cloth-wave, H100,
  # results/2026-12-08-h100/bar), whoever came first.
  "$bin" run --device cuda --scene funnel --pipeline c,grid --quiet --repeat 2 --out "$frames/warm-up-{pipeline}.h5" \
    --overwrite > /dev/null 2>&1 || echo "warm-up process failed"
  rm -f "$frames"/warm-up-*.h5
  i=0
  for s in $scenes; do
    (( $(date +%s) - start > cap )) && { echo "cap: $s and later scenes not run"; break; }
    # shellcheck disable=SC2046
    [[ -d "$frames/$s" ]] || "$bin" scenes generate "$s" $(generate_args "$s") --out "$frames/$s" > /dev/null ||
      { echo "generate $s failed"; continue; }
    each_binary $i "$(scene_of "$s")" "$s"
    i=$((i + 1))
    tar -C "$out" -cJf "$archive" .
  done
  if [[ "${BAR_10M:-0}" == 1 ]] && (( $(date +%s) - start <= cap )); then
    each_binary $i cloth-wave cloth-wave-10m --set res=2237 --set frames=4
  fi
  echo "end at $(($(date +%s) - start)) s"
} 2>&1 | tee "$out/bar.log"
tar -C "$out" -cJf "$archive" . && rm -rf "$out"
