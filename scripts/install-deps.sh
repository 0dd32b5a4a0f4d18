#!/usr/bin/env bash
# Installs the Debian packages cdbench needs, only those missing; no prompts; safe to re-run.
# Without options: what building and running cdbench needs (the compilers' packages and the
# libraries, GoogleTest's headers included so the one build directory also configures the
# tests). --python adds the Python tools the tests and the report scripts run with
# /usr/bin/python3 (h5py, numpy, matplotlib: about half the download, so the first
# `scripts/cdbench run` does without them), and pybind11 with Python's headers for the
# `cdbench` Python module (docs/library.md).
# --scenes also installs assimp-testmodels (BSD-3; 21 MB download, 74 MB installed), whose
# models the scenes bcn-jump, wuson-walk, skeleton-fbx, sydney-md2, crowd and crowd-large read.
# --scenes-extra installs the static scans: glmark2-data (bunny.obj, GPL-3+; 7 MB download)
# for bunny-drop, and libcgal-demo (CGAL's data.tar.gz with refined_elephant.off and
# armadillo.off, CC0; 24 MB download, pulls in libcgal-dev and a few Boost libraries: about
# 100 MB installed in all) for elephant-armadillo.
# --slurm installs slurmctld, slurmd, slurm-client and munge (Debian's slurm-wlm without its
# accounting daemon) for the `slurm` tests, which start their own one-node cluster; their
# services are not started by the install (see policy-rc.d below).
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  libcli11-dev nlohmann-json3-dev libhdf5-dev libassimp-dev libomp-dev zlib1g-dev
  libgtest-dev libgmock-dev libbenchmark-dev
)
for arg in "$@"; do
  case $arg in
    --python) packages+=(python3-h5py python3-numpy python3-matplotlib pybind11-dev python3-dev) ;;
    --scenes) packages+=(assimp-testmodels) ;;
    --scenes-extra) packages+=(glmark2-data libcgal-demo) ;;
    --slurm) packages+=(slurmctld slurmd slurm-client munge) ;;
    *) echo "install-deps: unknown option $arg (known: --python, --scenes, --scenes-extra, --slurm)" >&2; exit 2 ;;
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
# Without systemd (a container), the packages' postinst scripts start their services through
# their init scripts (munge's would leave a system munged running, and the install fails when a
# start fails). A policy-rc.d that denies every start, as Docker's Debian images ship, stops
# that; one made here is removed again when the install ends.
policy=/usr/sbin/policy-rc.d
if [[ ! -e $policy && ! -d /run/systemd/system ]]; then
  printf '#!/bin/sh\nexit 101\n' | "${as_root[@]}" tee "$policy" >/dev/null
  "${as_root[@]}" chmod 755 "$policy"
  trap '"${as_root[@]}" rm -f "$policy"' EXIT
fi
"${as_root[@]}" apt-get update -q >&2
"${as_root[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
