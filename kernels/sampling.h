// Cosine-weighted directions drawn from the counter-based generator.
#ifndef MBAO_SAMPLING_H
#define MBAO_SAMPLING_H

#include "mbao/philox.h"

// The random numbers of one decision, addressed by what the decision is about:
// the pixel, its camera sample, the bounce (0 for the camera ray) and the node
// of the estimator's tree within that bounce.
static inline Philox4x32 random_block(uint pixel, uint camera_sample, uint bounce, uint node,
                                      uint2 seed) {
  Philox4x32 counter;
  counter.v[0] = pixel;
  counter.v[1] = camera_sample;
  counter.v[2] = bounce;
  counter.v[3] = node;
  return philox4x32_10(counter, seed.x, seed.y);
}

// An orthonormal basis around unit n without branches on n's direction
// (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017).
static inline void orthonormal_basis(float3 n, float3* t, float3* b) {
  const float sign = copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  *t = (float3)(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  *b = (float3)(c, sign + n.y * n.y * a, -n.y);
}

// Malley's method: uniform on the unit disk, projected up to the hemisphere.
// Unit length up to rounding, as n, t and b are: not normalised again, which
// took PoCL's normalize a square root, a division and its guards for vectors
// too long or too short to square.
static inline float3 cosine_direction(float3 n, float u1, float u2) {
  const float r = sqrt(u1);
  // Not sincos(2 pi u2): PoCL takes that through its general argument reduction.
  const float cos_phi = cospi(2.0f * u2), sin_phi = sinpi(2.0f * u2);
  float3 t, b;
  orthonormal_basis(n, &t, &b);
  return r * cos_phi * t + r * sin_phi * b + sqrt(fmax(0.0f, 1.0f - u1)) * n;
}

#endif
