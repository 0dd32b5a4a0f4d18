#!/usr/bin/env bash
# Installs the Debian packages cdbench needs, only those missing; no prompts; safe to re-run.
# --scenes also installs assimp-testmodels (BSD-3; 21 MB download, 74 MB installed), whose
# animated models the scenes bcn-jump, wuson-walk and skeleton-fbx read.
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  libcli11-dev nlohmann-json3-dev libhdf5-dev libassimp-dev libomp-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-h5py python3-numpy python3-matplotlib
)
for arg in "$@"; do
  case $arg in
    --scenes) packages+=(assimp-testmodels) ;;
    *) echo "install-deps: unknown option $arg (known: --scenes)" >&2; exit 2 ;;
  esac
done
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
((${#missing[@]})) || exit 0
echo "install-deps: installing ${missing[*]}" >&2
as_root=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  as_root=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -q >&2
"${as_root[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
