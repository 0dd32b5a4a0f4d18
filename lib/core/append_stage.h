#pragma once
// Block-staged appends: the pairs and front nodes a block of a traversal kernel produces are
// collected in its shared memory and written out at the block's end with one global claim
// per output, instead of one claim on a device-wide counter per producing warp instruction.
//
// Why: every producer appends to a few counters that the whole GPU shares (the pair count,
// one count per front kind). Same-address atomics are served one after the other by one L2
// slice, whatever the number of lanes in each, and as slowly with a plain atomic per lane as
// with warp aggregation (bench/append_bench.cu); the traversals issue hundreds of
// thousands of such instructions a frame.
//
// A stage holds kCapacity entries; entries past that go to the global counter directly, as
// unstaged ones always do, so nothing is dropped and every entry is counted once.
//
// Staging costs each block a barrier and a flush at its end (an atomic's round trip), so it
// pays where blocks produce many entries and not where they produce few: update and the
// baselines' pair kernels gain everywhere, preserve gains on cloth and loses on n-body
// (fewer pairs per block of front nodes), so preserve stages only while the last frame's
// pairs per front node say it pays (FrontQuery::preserve). Smaller stages lost; the
// leaf-per-thread query of bvh and the brute force produce thousands of pairs per block,
// far past any stage, and lost staged: they append directly (docs/design.md "Constants
// and their measurements" has the figures). The order within an output changes, never the
// set: pairs are a set, and produced fronts are sorted afterwards (histogram or radix) or
// used in any order.
//
// The host executor passes no stage (null): sinks then append to the counters directly.
#include <cstdint>

#include "cdbench/core/atomics.h"
#include "cdbench/core/hd.h"
#include "cdbench/core/pair.h"
#include "cdbench/exec/tuning.h"

namespace cdb {

// A staged kernel's block has kStagedThreads threads (Exec::for_each_staged, exec/tuning.h):
// what a stage's capacity and the front pipelines' choice to stage preserve are sized against.

struct PairStage {
  static constexpr uint32_t kCapacity = 1024;
  uint32_t size;
  unsigned long long base;
  PrimPair pair[kCapacity];

  // True if staged; false: the stage is full, the caller appends directly.
  CDB_HD_INLINE bool put(PrimPair p) {
    if (size >= kCapacity) return false;
    const uint32_t s = atomic_add_relaxed(&size, 1u);
    if (s >= kCapacity) return false;
    pair[s] = p;
    return true;
  }

#if defined(__CUDACC__)
  // Thread 0, before a barrier that precedes every put.
  __device__ void reset() { size = 0; }

  // Every thread of the block, after a barrier that follows the last put: one claim on the
  // global count, then a coalesced copy. Slots past the capacity are counted, not written
  // (the caller grows the buffer and re-runs, as for direct appends).
  __device__ void flush(unsigned long long* count, PrimPair* out, unsigned long long capacity) {
    const uint32_t n = min(size, kCapacity);
    if (threadIdx.x == 0) base = n ? atomicAdd(count, static_cast<unsigned long long>(n)) : 0;
    __syncthreads();
    for (uint32_t j = threadIdx.x; j < n; j += blockDim.x)
      if (base + j < capacity) out[base + j] = pair[j];
  }
#endif
};

// Front nodes (query leaf, node, opt mark) of both kinds: internal [0] and external [1].
struct FrontStage {
  static constexpr uint32_t kCapacity = 512;
  uint32_t size[2];
  unsigned long long base[2];
  uint32_t prim[2][kCapacity];
  uint32_t node[2][kCapacity];
  uint8_t mark[2][kCapacity];

  CDB_HD_INLINE bool put(int kind, uint32_t p, uint32_t n, uint8_t m) {
    if (size[kind] >= kCapacity) return false;
    const uint32_t s = atomic_add_relaxed(&size[kind], 1u);
    if (s >= kCapacity) return false;
    prim[kind][s] = p;
    node[kind][s] = n;
    mark[kind][s] = m;
    return true;
  }

#if defined(__CUDACC__)
  __device__ void reset() { size[0] = size[1] = 0; }

  // As PairStage::flush, per kind: count[kind], out_*[kind], capacity[kind].
  __device__ void flush(unsigned long long* count, uint32_t* const* out_prim, uint32_t* const* out_node,
                        uint8_t* const* out_mark, const unsigned long long* capacity) {
    const uint32_t n[2] = {min(size[0], kCapacity), min(size[1], kCapacity)};
    if (threadIdx.x < 2) {
      const int k = int(threadIdx.x);
      base[k] = n[k] ? atomicAdd(&count[k], static_cast<unsigned long long>(n[k])) : 0;
    }
    __syncthreads();
    for (int k = 0; k < 2; ++k)
      for (uint32_t j = threadIdx.x; j < n[k]; j += blockDim.x) {
        const unsigned long long slot = base[k] + j;
        if (slot < capacity[k]) {
          out_prim[k][slot] = prim[k][j];
          out_node[k][slot] = node[k][j];
          out_mark[k][slot] = mark[k][j];
        }
      }
  }
#endif
};

// What a kernel that produces fronts stages: its pairs and its front nodes.
struct PairFrontStage {
  PairStage pairs;
  FrontStage front;
#if defined(__CUDACC__)
  __device__ void reset() {
    pairs.reset();
    front.reset();
  }
#endif
};

// What a probing preserve stages: its pairs, and per front kind the stop nodes its block's
// warps counted (PreserveFrontFn<true>), added to the global slots once per block at the
// flush instead of once per warp: the slots are a few addresses that every warp of the
// launch added to.
struct PairCountStage {
  PairStage pairs;
  unsigned long long met[2];
#if defined(__CUDACC__)
  __device__ void reset() {
    pairs.reset();
    met[0] = met[1] = 0;
  }
#endif
};

}  // namespace cdb
