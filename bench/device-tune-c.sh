#!/usr/bin/env bash
# Runs on the GPU machine from a device bundle: pipeline c under several quality factors
# and Formula 2 thresholds, next to static (b), on each scene, for docs/results.md.
# TUNE_SCENES, TUNE_QUALITY and TUNE_REFIT choose the cells.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bundle_env.sh"
bin=$bundle/bin
mkdir -p "$out"
for s in ${TUNE_SCENES:-cloth-ball n-body cloth-100k funnel-large}; do
  "$bin/cdbench" scenes generate "$s" --out "/tmp/frames-$s" >/dev/null
  echo "--- $s static"
  "$bin/cdbench" run --device cuda --scene "/tmp/frames-$s" --pipeline static --quiet 2>/dev/null | grep -E "commit|per frame"
  for q in ${TUNE_QUALITY:-1.5 2 3}; do
    for r in ${TUNE_REFIT:-0.01 0.05}; do
      echo "--- $s c quality $q threshold-refit $r"
      "$bin/cdbench" run --device cuda --scene "/tmp/frames-$s" --pipeline c --quiet \
        --restructure-quality "$q" --threshold-refit "$r" 2>/dev/null | grep -E "per frame|formula|  restructure "
    done
  done
done 2>&1 | tee "$out/tune-c.log"
