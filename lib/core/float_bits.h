#pragma once
// A float's bits as an unsigned integer and back, the same on the host and in kernels: no
// conversion and no arithmetic, so every bit pattern (NaN payloads included) survives.
#include <cstdint>

#include "cdbench/core/hd.h"

namespace cdb {

CDB_HD_INLINE uint32_t float_bits(float f) {
#if defined(__CUDA_ARCH__)
  return __float_as_uint(f);
#else
  uint32_t bits;
  __builtin_memcpy(&bits, &f, sizeof bits);
  return bits;
#endif
}

CDB_HD_INLINE float bits_float(uint32_t bits) {
#if defined(__CUDA_ARCH__)
  return __uint_as_float(bits);
#else
  float f;
  __builtin_memcpy(&f, &bits, sizeof f);
  return f;
#endif
}

}  // namespace cdb
