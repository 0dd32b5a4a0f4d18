#!/usr/bin/env bash
# Installs missing Debian packages, configures build/ (first time) and builds the targets
# given (default: everything, tests included). Quiet when everything is up to date.
# CDB_BUILD_DIR overrides the build directory.
#   scripts/build.sh              every target (what scripts/test runs)
#   scripts/build.sh cdbench      the program alone (what scripts/cdbench runs)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CDB_BUILD_DIR:-$root/build}
bash "$root/scripts/install-deps.sh"
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  echo "build: configuring $build (first use; docs/usage.md \"Building\")" >&2
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
fi
if [[ ! -x "$build/app/cdbench" ]]; then
  echo "build: compiling ${*:-every target} on $(nproc) cores (first use only; a few minutes)" >&2
fi
cmake --build "$build" ${1:+--target "$@"} >&2
