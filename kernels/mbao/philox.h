// Philox4x32-10 (Salmon et al., "Parallel random numbers: as easy as 1, 2, 3", SC 2011):
// a counter-based generator, so every random number is a pure function of
// (counter, key) and results do not depend on tiling, work-group size or device.
#ifndef MBAO_PHILOX_H
#define MBAO_PHILOX_H

#include "mbao/platform.h"

typedef struct Philox4x32 {
  mbao_u32 v[4];
} Philox4x32;

#define MBAO_PHILOX_M0 0xD2511F53u
#define MBAO_PHILOX_M1 0xCD9E8D57u
#define MBAO_PHILOX_W0 0x9E3779B9u
#define MBAO_PHILOX_W1 0xBB67AE85u

// The high word of the 64-bit product, which compilers turn into one multiply
// (PoCL's mul_hi(uint, uint) builds it from four 16-bit products).
MBAO_FN mbao_u32 philox_mulhi(mbao_u32 a, mbao_u32 b) { return (mbao_u32)(((mbao_u64)a * b) >> 32); }

MBAO_FN Philox4x32 philox4x32_10(Philox4x32 counter, mbao_u32 key0, mbao_u32 key1) {
  Philox4x32 x = counter;
  MBAO_UNROLL
  for (int round = 0; round < 10; ++round) {
    const mbao_u32 hi0 = philox_mulhi(MBAO_PHILOX_M0, x.v[0]);
    const mbao_u32 lo0 = MBAO_PHILOX_M0 * x.v[0];
    const mbao_u32 hi1 = philox_mulhi(MBAO_PHILOX_M1, x.v[2]);
    const mbao_u32 lo1 = MBAO_PHILOX_M1 * x.v[2];
    Philox4x32 y;
    y.v[0] = hi1 ^ x.v[1] ^ key0;
    y.v[1] = lo1;
    y.v[2] = hi0 ^ x.v[3] ^ key1;
    y.v[3] = lo0;
    x = y;
    key0 += MBAO_PHILOX_W0;
    key1 += MBAO_PHILOX_W1;
  }
  return x;
}

// A float uniform in [0, 1) from the top 24 bits, so every value is exact.
MBAO_FN float philox_unit_float(mbao_u32 bits) { return (float)(bits >> 8) * (1.0f / 16777216.0f); }

#endif
