#!/usr/bin/env bash
# The traversal kernels load each box as two 16-byte vectors (lib/bvh/traverse.h): the CUDA
# backend compiled to PTX for sm_90, no kernel of the queries or the front operations may
# hold a 4-byte float load from global memory. A box loaded through an address chosen by
# kind was split into eight such loads, and the steady frames ran 0.60-0.91x (H100,
# results/2026-12-07-h100/bar). Arguments: nvcc, the build directory.
set -u
nvcc=$1
build=$2
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if ! "$nvcc" -I"$build/layers/registry" -I"$build/layers/cdbench" -I"$build/layers/baselines" -O3 -DNDEBUG \
  -arch=sm_90 --expt-relaxed-constexpr -std=c++20 -x cu "$root/registry/cuda_backend.cu" -ptx -o "$tmp/backend.ptx"; then
  echo "FAIL registry/cuda_backend.cu did not compile to PTX"
  exit 1
fi
# Per kernel: its name, how many 4-byte and 16-byte float loads from global memory it holds.
awk '
  /^\.(visible )?\.entry / { name = $0; sub(/^\.(visible )?\.entry /, "", name); sub(/\(.*/, "", name) }
  /ld\.global(\.[a-z]+)*\.f32/ && name != "" { scalar[name]++ }
  /ld\.global(\.[a-z]+)*\.v4\.f32/ && name != "" { vector[name]++ }
  END { for (n in vector) print n, scalar[n] + 0, vector[n]; for (n in scalar) if (!(n in vector)) print n, scalar[n], 0 }
' "$tmp/backend.ptx" > "$tmp/loads.txt"
traversal='SelfQueryFn|CrossQueryFn|PreserveFrontFn|UpdateFrontFn|GenerateFrontFn|PatchFrontFn|RestructureFrontFn'
checked=$(grep -cE "$traversal" "$tmp/loads.txt")
split=$(grep -E "$traversal" "$tmp/loads.txt" | awk '$2 > 0')
if (( checked < 8 )); then
  echo "FAIL only $checked traversal kernels found in the PTX (expected the queries' and every front operation's)"
  exit 1
fi
if [[ -n $split ]]; then
  echo "FAIL traversal kernels with 4-byte float loads (kernel, 4-byte loads, 16-byte loads):"
  echo "$split" | head -5
  exit 1
fi
echo "ok   $checked traversal kernels load their boxes as 16-byte vectors only"
