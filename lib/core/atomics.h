#pragma once
// Atomics and coherent loads usable from functors on both executors.
//
// The bottom-up build and refit hand data between threads of different blocks. On the GPU
// the atomic itself is acquire-release at device scope (one atom.acq_rel.gpu, which costs
// less than the fence.sc pair of __threadfence around a relaxed atomic), and the reader
// then reads the other thread's data with ld.global.cg, which bypasses the non-coherent
// L1. Without both, Hopper hands out stale boxes (the paper's public code hangs or corrupts
// its tree there).
#include <cstdint>

#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

#if defined(__CUDACC__)
#include <cuda/atomic>
#endif
#if !defined(__CUDA_ARCH__)
#include <atomic>
#endif

namespace cdb {

CDB_HD_INLINE uint32_t atomic_exchange_acq_rel(uint32_t* p, uint32_t v) {
#if defined(__CUDA_ARCH__)
  return cuda::atomic_ref<uint32_t, cuda::thread_scope_device>(*p).exchange(v, cuda::memory_order_acq_rel);
#else
  return std::atomic_ref<uint32_t>(*p).exchange(v, std::memory_order_acq_rel);
#endif
}

CDB_HD_INLINE uint32_t atomic_add_acq_rel(uint32_t* p, uint32_t v) {
#if defined(__CUDA_ARCH__)
  return cuda::atomic_ref<uint32_t, cuda::thread_scope_device>(*p).fetch_add(v, cuda::memory_order_acq_rel);
#else
  return std::atomic_ref<uint32_t>(*p).fetch_add(v, std::memory_order_acq_rel);
#endif
}

// The same hand-over between threads of one block (one tile of Exec::for_each_tile), on a
// counter in shared memory: block-scope fences are enough, and cost far less than the
// device-scope ones above.
CDB_HD_INLINE uint32_t atomic_add_acq_rel_block(uint32_t* p, uint32_t v) {
#if defined(__CUDA_ARCH__)
  return cuda::atomic_ref<uint32_t, cuda::thread_scope_block>(*p).fetch_add(v, cuda::memory_order_acq_rel);
#else
  return std::atomic_ref<uint32_t>(*p).fetch_add(v, std::memory_order_acq_rel);
#endif
}

// Floats handed over between threads of one block through shared memory (the refit's
// in-tile boxes): written and read with block-scope atomics. The order comes from the
// acquire-release arrival atomic beside them either way, and plain accesses would do on the
// hardware; but compute-sanitizer's racecheck does not model that order and reports plain
// ones as hazards, and a race checker that stays silent on correct code is worth a few
// shared-memory atomics a level. Relaxed: the arrival atomic orders them.
CDB_HD_INLINE void handover_store(float* p, float v) {
#if defined(__CUDA_ARCH__)
  atomicExch_block(p, v);
#else
  *p = v;
#endif
}

CDB_HD_INLINE float handover_load(float* p) {
#if defined(__CUDA_ARCH__)
  return __uint_as_float(atomicOr_block(reinterpret_cast<unsigned*>(p), 0u));
#else
  return *p;
#endif
}

// Raises *p to v if v is larger (the refit top's deepest slot, bvh/refit_top.h).
CDB_HD_INLINE void atomic_max_relaxed(uint32_t* p, uint32_t v) {
#if defined(__CUDA_ARCH__)
  atomicMax(p, v);
#else
  std::atomic_ref<uint32_t> a(*p);
  uint32_t seen = a.load(std::memory_order_relaxed);
  while (seen < v && !a.compare_exchange_weak(seen, v, std::memory_order_relaxed)) {
  }
#endif
}

CDB_HD_INLINE uint32_t atomic_add_relaxed(uint32_t* p, uint32_t v) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(p, v);
#else
  return std::atomic_ref<uint32_t>(*p).fetch_add(v, std::memory_order_relaxed);
#endif
}

CDB_HD_INLINE unsigned long long atomic_add_relaxed(unsigned long long* p, unsigned long long v) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(p, v);
#else
  return std::atomic_ref<unsigned long long>(*p).fetch_add(v, std::memory_order_relaxed);
#endif
}

CDB_HD_INLINE uint32_t load_coherent(const uint32_t* p) {
#if defined(__CUDA_ARCH__)
  return __ldcg(p);
#else
  return *p;
#endif
}

CDB_HD_INLINE vec4f load_coherent(const vec4f* p) {
#if defined(__CUDA_ARCH__)
  const float4 v = __ldcg(reinterpret_cast<const float4*>(p));
  return {v.x, v.y, v.z, v.w};
#else
  return *p;
#endif
}

// Adds one to *counter for the calling thread and returns the value it had: a relaxed
// fetch-add. On the GPU the lanes of a warp that claim from the same counter together (the
// coalesced group, split by address) share one atomic and take consecutive values by lane
// rank. Front producers and the histogram scatter claim millions of slots a frame from a few
// hot counters, where aggregation pays (docs/experiments.md).
template <class T>
CDB_HD_INLINE T claim_one(T* counter) {
#if defined(__CUDA_ARCH__)
  const unsigned active = __activemask();
  const unsigned same = __match_any_sync(active, reinterpret_cast<unsigned long long>(counter));
  const int leader = __ffs(same) - 1;
  const unsigned lane = threadIdx.x & 31u;
  T base = 0;
  if (lane == unsigned(leader)) base = atomicAdd(counter, static_cast<T>(__popc(same)));
  base = __shfl_sync(same, base, leader);
  return base + static_cast<T>(__popc(same & ((1u << lane) - 1u)));
#else
  return atomic_add_relaxed(counter, T(1));
#endif
}

// Adds one to *counter for the calling thread and wants no value back. The lanes of a warp
// that count on the same address together share one atomic, as in claim_one, but the
// leader's add is a reduction (RED) whose result nobody waits for: the histogram sort's count
// logs take one such add per produced front node, and a fetch-add there stalled every push
// for an atomic's round trip.
template <class T>
CDB_HD_INLINE void count_one(T* counter) {
#if defined(__CUDA_ARCH__)
  const unsigned same = __match_any_sync(__activemask(), reinterpret_cast<unsigned long long>(counter));
  if ((threadIdx.x & 31u) == unsigned(__ffs(same) - 1)) atomicAdd(counter, static_cast<T>(__popc(same)));
#else
  atomic_add_relaxed(counter, T(1));
#endif
}

}  // namespace cdb
