// The spatial filter of SPEC 7.3: an edge-aware a-trous wavelet filter
// (Dammertz et al. 2010) guided by the G-buffer (SPEC 7.2) and each pixel's
// variance (SPEC 7.1), as in SVGF (Schied et al. 2017). One launch per
// iteration, a work item per pixel, rows of the image in order.
#include "mbao/gbuffer.h"

static inline int texel_hit(GBufferTexel g) { return g.t > 0.0f; }

static inline float3 texel_point(GBufferTexel g) { return (float3)(g.x, g.y, g.z); }

static inline float3 texel_normal(GBufferTexel g) { return (float3)(g.nx, g.ny, g.nz); }

// g(v): the variance blurred by (1, 2, 1)^2 over the 3 x 3 taps that hit,
// normalised over them; what the value weights of an iteration compare with.
__kernel void denoise_blur_variance(__global const GBufferTexel* gbuffer, __global const float* variance,
                                    uint width, uint height, __global float* blurred) {
  const uint pixel = get_global_id(0);
  if (pixel >= width * height) return;
  const int x = (int)(pixel % width), y = (int)(pixel / width);
  float sum = 0.0f, weights = 0.0f;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = x + dx, qy = y + dy;
      if (qx < 0 || qy < 0 || qx >= (int)width || qy >= (int)height) continue;
      const uint q = (uint)qy * width + (uint)qx;
      if (!texel_hit(gbuffer[q])) continue;
      const float w = (float)((2 - abs(dx)) * (2 - abs(dy)));
      sum += w * variance[q];
      weights += w;
    }
  blurred[pixel] = weights > 0.0f ? sum / weights : 0.0f;
}

typedef struct FilterWeights {
  float sigma_plane, sigma_value;
  uint sigma_normal;
} FilterWeights;

// x^n by squaring: no logarithm per tap (it took a fifth of the filter's time on PoCL).
static inline float power(float x, uint n) {
  float result = 1.0f;
  for (; n; n >>= 1, x *= x)
    if (n & 1u) result *= x;
  return result;
}

// w(p, q) of SPEC 7.3 for a tap other than p itself.
static inline float edge_weight(GBufferTexel p, GBufferTexel q, float value_p, float value_q, float value_scale,
                                const FilterWeights* f) {
  const float3 n = texel_normal(p);
  const float plane = fabs(dot(n, texel_point(q) - texel_point(p))) / (f->sigma_plane * p.footprint);
  const float facing = fmax(0.0f, dot(n, texel_normal(q)));
  return power(facing, f->sigma_normal) * exp(-plane - fabs(value_p - value_q) / value_scale);
}

// One iteration: taps 2^i = `step` pixels apart, weighted by the B3 spline and w.
__kernel void denoise_atrous(__global const GBufferTexel* gbuffer, __global const float* ao,
                             __global const float* variance, __global const float* blurred_variance, uint width,
                             uint height, uint step, float sigma_plane, uint sigma_normal, float sigma_value,
                             __global float* ao_out, __global float* variance_out) {
  const uint pixel = get_global_id(0);
  if (pixel >= width * height) return;
  const GBufferTexel p = gbuffer[pixel];
  if (!texel_hit(p)) {  // a miss keeps its value
    ao_out[pixel] = ao[pixel];
    variance_out[pixel] = variance[pixel];
    return;
  }
  const FilterWeights f = {sigma_plane, sigma_value, sigma_normal};
  const float spline[3] = {6.0f / 16.0f, 4.0f / 16.0f, 1.0f / 16.0f};
  const int x = (int)(pixel % width), y = (int)(pixel / width);
  const float value_p = ao[pixel];
  const float value_scale = sigma_value * sqrt(blurred_variance[pixel]) + 1e-6f;
  float sum = 0.0f, weights = 0.0f, variance_sum = 0.0f;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int qx = x + dx * (int)step, qy = y + dy * (int)step;
      if (qx < 0 || qy < 0 || qx >= (int)width || qy >= (int)height) continue;
      const uint q = (uint)qy * width + (uint)qx;
      const GBufferTexel tap = gbuffer[q];
      if (!texel_hit(tap)) continue;
      const float w = dx == 0 && dy == 0 ? 1.0f : edge_weight(p, tap, value_p, ao[q], value_scale, &f);
      const float hw = spline[abs(dx)] * spline[abs(dy)] * w;
      sum += hw * ao[q];
      weights += hw;
      variance_sum += hw * hw * variance[q];
    }
  ao_out[pixel] = clamp(sum / weights, 0.0f, 1.0f);  // a weighted mean: only rounding could leave [0, 1]
  variance_out[pixel] = variance_sum / (weights * weights);
}
