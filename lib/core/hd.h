#pragma once
// One host/device annotation for every function that runs on both executors.
#if defined(__CUDACC__)
#define CDB_HD __host__ __device__
#define CDB_HD_INLINE __host__ __device__ __forceinline__
#else
#define CDB_HD
#define CDB_HD_INLINE inline
#endif
