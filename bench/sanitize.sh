#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle: compute-sanitizer's memcheck (with leak
# check), synccheck, initcheck and racecheck over every pipeline on a small folding cloth,
# one log per tool, archived as $OUT/sanitize.tar.xz, and a summary line per tool in
# $OUT/sanitize-summary.txt. A fixed front cycle of 3, so that the 8 frames probe, update
# (sprouts shared in warps) and replay recorded frames; periodic generates and restructure
# restructures, both spread over warps.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
top=$out
out=$top/sanitize
mkdir -p "$out"
pipelines=${PIPELINES:-a,b,c,unordered,periodic,restructure,radix-order,reference,bvh,grid,hash,sweep}
scene=(--scene cloth-ball --set res=40 --set frames=8 --front-cycle 3)
for tool in memcheck synccheck initcheck racecheck; do
  extra=()
  [[ $tool == memcheck ]] && extra=(--leak-check full)
  compute-sanitizer --tool "$tool" "${extra[@]}" --error-exitcode 9 \
    "$bundle/bin/cdbench" run --device cuda "${scene[@]}" --pipeline "$pipelines" --quiet \
    >"$out/$tool.log" 2>&1
  echo "$tool: exit $? $(grep -E 'ERROR SUMMARY|RACECHECK SUMMARY|LEAK SUMMARY' "$out/$tool.log" | tr '\n' ' ')"
done | tee "$top/sanitize-summary.txt"
tar -C "$out" -cJf "$top/sanitize.tar.xz" . && rm -rf "$out"
