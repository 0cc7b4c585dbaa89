// Exact float steps made from a float's bits: the next float in a direction,
// and the power of two that scales a vector's largest component into [1, 2).
// The library's nextafter, ilogb and ldexp do the same, but PoCL's vector code
// for them costs a ray-traced frame a few percent: every hit calls them.
// Shared by the host, which tests them against the library, and the kernels.
#ifndef MBAO_FLOAT_STEPS_H
#define MBAO_FLOAT_STEPS_H

#include "mbao/platform.h"

// x moved by one float toward the sign of `toward`, or x where `toward` is 0:
// nextafter(x, toward * infinity) for finite x. Away from zero adds one to the
// magnitude's bits, toward zero takes one; a zero steps to the smallest
// denormal of toward's sign. x's sign is read from its bits, so that a device
// that flushes denormals in comparisons steps them as the host does.
MBAO_FN float float_step_toward(float x, float toward) {
  const mbao_u32 bits = mbao_float_as_u32(x);
  const mbao_u32 away_from_zero = (mbao_u32)(((bits >> 31) == 0u) == (toward > 0.0f));
  const mbao_u32 stepped = bits + 2u * away_from_zero - 1u;
  const mbao_u32 from_zero = toward < 0.0f ? 0x80000001u : 0x00000001u;
  const mbao_u32 moved = (bits & 0x7fffffffu) == 0u ? from_zero : stepped;
  return mbao_u32_as_float(toward == 0.0f ? bits : moved);
}

// 2^-ilogb(x) for a finite x > 0, as two factors, each a normal float: one
// normal float cannot hold it where x is below 2^-127 or from 2^127 up. Multiplying v
// by `high`, then by `low` gives ldexp(v, -ilogb(x)) exactly for every v from
// x 2^-62 to x in magnitude (the product after `high` is a normal float then)
// and for zero; smaller v may round differently in their last denormal bit.
typedef struct PowerOfTwo {
  float high, low;
} PowerOfTwo;

MBAO_FN PowerOfTwo inverse_power_of_two(float x) {
  const mbao_u32 bits = mbao_float_as_u32(x);
  const int biased = (int)(bits >> 23);
  // A denormal's exponent is its highest set bit's, at 2^-149 a unit.
  const int exponent = biased != 0 ? biased - 127 : 31 - (int)mbao_clz(bits) - 149;  // ilogb(x)
  const int high = -exponent / 2, low = -exponent - high;                            // each in [-64, 75]
  const PowerOfTwo p = {mbao_u32_as_float((mbao_u32)(high + 127) << 23),
                        mbao_u32_as_float((mbao_u32)(low + 127) << 23)};
  return p;
}

#endif
