#!/usr/bin/env bash
# Layers (docs/design.md "Layers"): every include names a layer the including directory may
# use, spelled with its prefix and without "..", and the build refuses an include of a layer
# a target does not link (the probes of tests/layers/ must each fail to compile).
set -u
build=$1
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
failures=0
fail() { echo "FAIL $1"; failures=$((failures + 1)); }

# The prefixes each directory may include; "own": also headers beside the including file,
# by bare name (examples/, a project of its own on the installed package).
declare -A allowed=(
  [lib]="cdbench"
  [baselines]="cdbench baselines"
  [scenes]="cdbench scenes"
  [registry]="cdbench baselines registry"
  [api]="cdbench registry"
  [python]="cdbench"
  [examples]="cdbench own"
  [harness]="cdbench scenes registry harness"
  # The measuring loop: the engine and the rest of the harness, nothing of app/ (whose
  # headers are bare names) nor of the registry or the scenes.
  [harness/measure]="cdbench harness"
)
cd "$root" || exit 1
for dir in "${!allowed[@]}"; do
  bad=0
  while IFS= read -r line; do
    file=${line%%:*}
    name=$(sed -E 's/.*#\s*include\s+"([^"]+)".*/\1/' <<<"${line#*:}")
    prefix=${name%%/*}
    if [[ $name != */* && " ${allowed[$dir]} " == *" own "* && -f $(dirname "$file")/$name ]]; then
      continue
    fi
    if [[ $name == *..* || $name != */* || " ${allowed[$dir]} " != *" $prefix "* ]]; then
      fail "$file includes \"$name\": $dir/ may include only ${allowed[$dir]// /, }"
      bad=1
    fi
  done < <(git grep -n -E '^\s*#\s*include\s+"' -- "$dir" | sed -E 's/^([^:]+):[0-9]+:/\1:/')
  ((bad)) || echo "ok   $dir/ includes only ${allowed[$dir]// /, }"
done

for probe in engine engine_scenes baselines scenes registry api measure; do
  header=$(sed -nE 's/^#include "([^"]+)"/\1/p' "tests/layers/wrong_$probe.cpp")
  out=$(cmake --build "$build" --target "layer_probe_$probe" 2>&1)
  if [[ $? -ne 0 ]] && grep -qF "$header: No such file or directory" <<<"$out"; then
    echo "ok   the build refuses tests/layers/wrong_$probe.cpp ($header)"
  else
    fail "tests/layers/wrong_$probe.cpp: expected '$header: No such file or directory', got:"
    tail -5 <<<"$out" | sed 's/^/    /'
  fi
done
if ((failures)); then echo "$failures layers test(s) failed"; exit 1; fi
echo "all layers tests passed"
