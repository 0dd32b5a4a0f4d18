#pragma once
// One host/device annotation for every function that runs on both executors.
// CDB_HD_CALL: a header function kept out of line in device code, where inlining every call
// of a large body (the exact integer arithmetic of narrow/wide_int.h) would multiply the
// kernel's code and nvcc's compile time and memory; on the host the compiler chooses.
#if defined(__CUDACC__)
#define CDB_HD __host__ __device__
#define CDB_HD_INLINE __host__ __device__ __forceinline__
#define CDB_HD_CALL __host__ __device__ __noinline__ inline
#else
#define CDB_HD
#define CDB_HD_INLINE inline
#define CDB_HD_CALL inline
#endif
