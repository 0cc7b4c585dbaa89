// The point of the unit circle at an angle, without a call to a math library:
// on PoCL a call to sin or cos keeps the loop over a group's work items from
// becoming vector code, and HBAO draws a direction per pixel and direction.
// Shared by the host, which tests it against double precision, and the kernels.
#ifndef MBAO_UNIT_CIRCLE_H
#define MBAO_UNIT_CIRCLE_H

#include "mbao/platform.h"

typedef struct UnitCirclePoint {
  float c, s;  // cos and sin of the angle
} UnitCirclePoint;

// For angles in [0, 2 pi]: the quadrant is taken out, leaving r in about
// [-pi/4, pi/4], and sin r and cos r are Cephes' single-precision minimax
// polynomials (sinf.c, cosf.c: relative error under 2^-24 there). Each of c
// and s is within 5e-7 of the exact value at the given float angle
// (tests/cpp/test_unit_circle.cpp), most of it the rounding of quadrant * pi/2.
MBAO_FN UnitCirclePoint unit_circle_point(float angle) {
  const float quadrant = mbao_floor(angle * 0.63661977236758134f + 0.5f);  // 2 / pi
  const float r = angle - quadrant * 1.57079632679489662f;
  const float r2 = r * r;
  const float sin_r = r + r * r2 * (-1.6666654611e-1f + r2 * (8.3321608736e-3f + r2 * -1.9515295891e-4f));
  const float cos_r =
      1.0f - 0.5f * r2 + r2 * r2 * (4.166664568298827e-2f + r2 * (-1.388731625493765e-3f + r2 * 2.443315711809948e-5f));
  // Selects rather than a switch on the quadrant, which PoCL's vectoriser refuses.
  const int q = (int)quadrant & 3;
  const float c = (q & 1) ? sin_r : cos_r, s = (q & 1) ? cos_r : sin_r;
  const UnitCirclePoint p = {((q + 1) & 2) ? -c : c, (q & 2) ? -s : s};
  return p;
}

#endif
