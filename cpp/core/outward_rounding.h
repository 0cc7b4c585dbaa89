// Doubles rounded to float toward -infinity or +infinity: a box computed in
// double stays a box around the same points once it is float.
#pragma once

#include <cstdint>
#include <cstring>

namespace mbao {

// x rounded to a float toward -infinity (direction -1) or +infinity (+1), for x
// not NaN. Which way the nearest float missed x is a coin flip to the branch
// predictor, and the kd-tree build rounds millions of corners: the step is
// integer arithmetic on the float's bits, with masks where a multiply or a
// ternary would become a branch again; not std::nextafter, a library call.
inline float round_outward(double x, int direction) {
  const float nearest = float(x);
  std::uint32_t bits;
  std::memcpy(&bits, &nearest, sizeof bits);
  const std::uint32_t missed = direction < 0 ? double(nearest) > x : double(nearest) < x;
  // Away from zero adds one to the magnitude's bits, toward zero takes one. A
  // zero that missed x has x's sign (conversion keeps it), so the step from it
  // goes away from zero, to the smallest denormal of that sign.
  const std::uint32_t away_from_zero = std::uint32_t((bits >> 31) == std::uint32_t(direction < 0));
  bits += (2u * away_from_zero - 1u) & (0u - missed);
  float rounded;
  std::memcpy(&rounded, &bits, sizeof rounded);
  return rounded;
}

inline float round_down(double x) { return round_outward(x, -1); }
inline float round_up(double x) { return round_outward(x, +1); }

}  // namespace mbao
