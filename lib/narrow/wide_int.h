#pragma once
// Exact signed integers of a fixed capacity (kWideLimbs 32-bit limbs, 1792 bits) with +, -
// and *, for the exact path of the proximity predicates (proximity.h). No allocation: the
// same code runs in CUDA kernels.
//
// Floats enter as integers in units of 2^-149, the spacing of the smallest subnormal: every
// float x is an integer multiple of 2^-149, so X = x * 2^149 is an integer, |X| < 2^277.
// A polynomial of degree g in such integers is the polynomial of the floats times 2^(149 g),
// so the sign of a homogeneous polynomial is the same in both. Nothing here checks for
// overflow: the capacity is sized for the largest value proximity.h forms (below 2^1677,
// its comment derives it), and a product needs the sum of its factors' limbs, at most 54.
#include <cstdint>
#include <cstring>

#include "cdbench/core/hd.h"

namespace cdb {

inline constexpr int kWideLimbs = 56;

struct WideInt {
  uint32_t limb[kWideLimbs];  // magnitude, least significant limb first; only [0, size) is set
  int size;                   // limbs in use, the top one nonzero; 0 for zero
  int sign;                   // -1, 0 or 1

  // x * 2^149, exactly.
  CDB_HD_CALL static WideInt of_float(float x) {
    uint32_t bits;
    memcpy(&bits, &x, sizeof bits);
    const uint32_t biased = (bits >> 23) & 0xFFu, fraction = bits & 0x7FFFFFu;
    // x = fraction * 2^-149 (subnormal) or (2^23 + fraction) * 2^(biased - 150): in units of
    // 2^-149 that is the significand shifted left by 0 or by biased - 1.
    const uint64_t significand = biased == 0 ? fraction : (fraction | 0x800000u);
    const int shift = biased == 0 ? 0 : int(biased) - 1;
    WideInt r;
    r.sign = significand == 0 ? 0 : (bits >> 31) ? -1 : 1;
    const int limb = shift / 32, bit = shift % 32;
    const uint64_t shifted = significand << bit;  // below 2^56
    for (int i = 0; i < limb; ++i) r.limb[i] = 0;
    r.limb[limb] = uint32_t(shifted);
    r.limb[limb + 1] = uint32_t(shifted >> 32);
    r.size = limb + 2;
    r.trim();
    return r;
  }
  // (x - y) * 2^149, exactly.
  CDB_HD_CALL static WideInt of_difference(float x, float y);

  CDB_HD_INLINE void trim() {
    while (size > 0 && limb[size - 1] == 0) --size;
    if (size == 0) sign = 0;
  }
};

namespace wide {

// -1, 0, 1 as |a| <, ==, > |b|.
CDB_HD_INLINE int compare_magnitudes(const WideInt& a, const WideInt& b) {
  if (a.size != b.size) return a.size < b.size ? -1 : 1;
  for (int i = a.size - 1; i >= 0; --i)
    if (a.limb[i] != b.limb[i]) return a.limb[i] < b.limb[i] ? -1 : 1;
  return 0;
}

// |a| + |b| with the given sign.
CDB_HD_INLINE WideInt add_magnitudes(const WideInt& a, const WideInt& b, int sign) {
  const WideInt& longer = a.size >= b.size ? a : b;
  const WideInt& shorter = a.size >= b.size ? b : a;
  WideInt r;
  uint64_t carry = 0;
  for (int i = 0; i < longer.size; ++i) {
    const uint64_t t = uint64_t(longer.limb[i]) + (i < shorter.size ? shorter.limb[i] : 0u) + carry;
    r.limb[i] = uint32_t(t);
    carry = t >> 32;
  }
  r.limb[longer.size] = uint32_t(carry);
  r.size = longer.size + 1;
  r.sign = sign;
  r.trim();
  return r;
}

// |a| - |b| with the given sign; |a| >= |b|.
CDB_HD_INLINE WideInt subtract_magnitudes(const WideInt& a, const WideInt& b, int sign) {
  WideInt r;
  int64_t borrow = 0;
  for (int i = 0; i < a.size; ++i) {
    int64_t t = int64_t(a.limb[i]) - (i < b.size ? int64_t(b.limb[i]) : 0) - borrow;
    borrow = t < 0;
    if (t < 0) t += int64_t(1) << 32;
    r.limb[i] = uint32_t(t);
  }
  r.size = a.size;
  r.sign = sign;
  r.trim();
  return r;
}

}  // namespace wide

CDB_HD_INLINE WideInt operator-(WideInt a) {
  a.sign = -a.sign;
  return a;
}

CDB_HD_CALL WideInt operator+(const WideInt& a, const WideInt& b) {
  if (b.sign == 0) return a;
  if (a.sign == 0) return b;
  if (a.sign == b.sign) return wide::add_magnitudes(a, b, a.sign);
  const int c = wide::compare_magnitudes(a, b);
  if (c == 0) {
    WideInt zero;
    zero.size = 0;
    zero.sign = 0;
    return zero;
  }
  return c > 0 ? wide::subtract_magnitudes(a, b, a.sign) : wide::subtract_magnitudes(b, a, b.sign);
}

CDB_HD_CALL WideInt operator-(const WideInt& a, const WideInt& b) { return a + (-b); }

// Schoolbook product; a.size + b.size <= kWideLimbs (see the file comment).
CDB_HD_CALL WideInt operator*(const WideInt& a, const WideInt& b) {
  WideInt r;
  r.sign = a.sign * b.sign;
  if (r.sign == 0) {
    r.size = 0;
    return r;
  }
  r.size = a.size + b.size;
  for (int i = 0; i < r.size; ++i) r.limb[i] = 0;
  for (int i = 0; i < a.size; ++i) {
    uint64_t carry = 0;
    for (int j = 0; j < b.size; ++j) {
      // At most (2^32 - 1)^2 + 2 (2^32 - 1) = 2^64 - 1: no overflow.
      const uint64_t t = uint64_t(a.limb[i]) * b.limb[j] + r.limb[i + j] + carry;
      r.limb[i + j] = uint32_t(t);
      carry = t >> 32;
    }
    r.limb[i + b.size] = uint32_t(carry);
  }
  r.trim();
  return r;
}

CDB_HD_CALL WideInt WideInt::of_difference(float x, float y) { return of_float(x) - of_float(y); }

}  // namespace cdb
