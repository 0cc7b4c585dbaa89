// Cosine-weighted directions drawn from the counter-based generator.
#ifndef MBAO_SAMPLING_H
#define MBAO_SAMPLING_H

#include "mbao/philox.h"

// The random numbers of one decision, addressed by what the decision is about:
// the pixel, its camera sample, the bounce (0 for the camera ray) and the node
// of the estimator's tree within that bounce.
static inline Philox4x32 random_block(uint pixel, uint camera_sample, uint bounce, uint node, uint2 seed) {
  Philox4x32 counter;
  counter.v[0] = pixel;
  counter.v[1] = camera_sample;
  counter.v[2] = bounce;
  counter.v[3] = node;
  return philox4x32_10(counter, seed.x, seed.y);
}

// random_block for the nodes first_node .. first_node + 3 at once: word k of
// block first_node + j in lane j of v[k]. The same rounds on vectors, so the
// same bits, where a CPU would otherwise run four blocks one after another.
static inline void random_blocks_x4(uint pixel, uint camera_sample, uint bounce, uint first_node, uint2 seed,
                                    uint4 v[4]) {
  v[0] = (uint4)(pixel);
  v[1] = (uint4)(camera_sample);
  v[2] = (uint4)(bounce);
  v[3] = (uint4)(first_node) + (uint4)(0u, 1u, 2u, 3u);
  uint key0 = seed.x, key1 = seed.y;
  for (int round = 0; round < 10; ++round) {
    const uint4 hi0 = convert_uint4((convert_ulong4(v[0]) * (ulong)MBAO_PHILOX_M0) >> 32);
    const uint4 lo0 = v[0] * MBAO_PHILOX_M0;
    const uint4 hi1 = convert_uint4((convert_ulong4(v[2]) * (ulong)MBAO_PHILOX_M1) >> 32);
    const uint4 lo1 = v[2] * MBAO_PHILOX_M1;
    v[0] = hi1 ^ v[1] ^ key0;
    v[1] = lo1;
    v[2] = hi0 ^ v[3] ^ key1;
    v[3] = lo0;
    key0 += MBAO_PHILOX_W0;
    key1 += MBAO_PHILOX_W1;
  }
}

// philox_unit_float lane by lane.
static inline float4 philox_unit_floats(uint4 bits) { return convert_float4(bits >> 8) * (1.0f / 16777216.0f); }

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

// cosine_direction for four (u1, u2) pairs, the directions' x, y and z in the
// lanes of *x, *y and *z: the same operations in the same order, so the same
// bits (tests/cpp/test_sampling.cpp).
static inline void cosine_directions_x4(float3 n, float4 u1, float4 u2, float4* x, float4* y, float4* z) {
  const float4 r = sqrt(u1);
  const float4 cos_phi = cospi(2.0f * u2), sin_phi = sinpi(2.0f * u2);
  float3 t, b;
  orthonormal_basis(n, &t, &b);
  const float4 along_t = r * cos_phi, along_b = r * sin_phi, along_n = sqrt(fmax(0.0f, 1.0f - u1));
  *x = along_t * t.x + along_b * b.x + along_n * n.x;
  *y = along_t * t.y + along_b * b.y + along_n * n.y;
  *z = along_t * t.z + along_b * b.z + along_n * n.z;
}

#endif
