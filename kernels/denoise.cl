// The spatial filter of SPEC 7.3: an edge-aware a-trous wavelet filter
// (Dammertz et al. 2010) guided by the G-buffer (SPEC 7.2) and each pixel's
// variance (SPEC 7.1), as in SVGF (Schied et al. 2017). An iteration is two
// launches: the interior, where every tap's column lies in the image, over a
// grid of columns x rows whose groups each hold neighbouring pixels of one
// row, and the strips of 2 step columns at the left and right.
//
// Written for PoCL's vectoriser, which turns the loop over a group's work
// items into vector code only where its body has no loops, no OpenCL vector
// types and no struct loads: the taps are unrolled, the G-buffer is read plane
// by plane, and a tap outside the image weighs 0 instead of being skipped. In
// the interior a tap's index is its pixel's plus a constant, so that its loads
// are vector loads.
#include "mbao/gbuffer.h"
#include "mbao/limits.h"

#define ALWAYS_INLINE __attribute__((always_inline)) static inline

typedef struct Images {
  const __global float* gbuffer;
  const __global float *ao, *variance;
  int width, height;
} Images;

typedef struct FilterWeights {
  float sigma_plane, sigma_value;
  uint sigma_normal;
} FilterWeights;

typedef struct Tap {
  int index;   // of the tap's pixel, or of the nearest in the image where the tap is outside it
  int inside;  // whether the tap is in the image
} Tap;

// The tap (dx, dy) pixels from (x, y); `columns_inside`: its column is known to be in the image.
ALWAYS_INLINE Tap tap_at(const Images* images, int x, int y, int dx, int dy, int columns_inside) {
  const int qx = x + dx, qy = y + dy;
  const int column = columns_inside ? qx : clamp(qx, 0, images->width - 1);
  const Tap tap = {clamp(qy, 0, images->height - 1) * images->width + column,
                   qy >= 0 && qy < images->height && (columns_inside || (qx >= 0 && qx < images->width))};
  return tap;
}

// g(v) at (x, y): the variance blurred by (1, 2, 1)^2 over the 3 x 3 taps
// that hit, normalised over them; what the value weights compare with.
ALWAYS_INLINE float blurred_variance(const Images* images, int x, int y, int columns_inside) {
  const __global float* t = filter_gbuffer_plane(images->gbuffer, images->width * images->height, GBUFFER_T);
  float sum = 0.0f, weights = 0.0f;
#pragma unroll
  for (int dy = -1; dy <= 1; ++dy)
#pragma unroll
    for (int dx = -1; dx <= 1; ++dx) {
      const Tap tap = tap_at(images, x, y, dx, dy, columns_inside);
      const float w = tap.inside && t[tap.index] > 0.0f ? (float)((2 - abs(dx)) * (2 - abs(dy))) : 0.0f;
      sum += w * images->variance[tap.index];
      weights += w;
    }
  return sum / weights;
}

// x^n for n < 2^MBAO_NORMAL_EXPONENT_BITS, by squaring: no logarithm, and a
// loop of fixed count, which unrolls.
ALWAYS_INLINE float power(float x, uint n) {
  float result = 1.0f;
#pragma unroll
  for (int bit = 0; bit < MBAO_NORMAL_EXPONENT_BITS; ++bit, x *= x) result *= (n >> bit) & 1u ? x : 1.0f;
  return result;
}

// One iteration's filtered value and variance at (x, y): taps `step` pixels
// apart, weighted by the B3 spline and w(p, q) of SPEC 7.3.
ALWAYS_INLINE void filter_pixel(const Images* images, FilterWeights f, int x, int y, int step, int columns_inside,
                                __global float* ao_out, __global float* variance_out) {
  const uint pixels = images->width * images->height;
  const __global float* g = images->gbuffer;
  const __global float *gx = filter_gbuffer_plane(g, pixels, GBUFFER_X),
                       *gy = filter_gbuffer_plane(g, pixels, GBUFFER_Y),
                       *gz = filter_gbuffer_plane(g, pixels, GBUFFER_Z),
                       *gt = filter_gbuffer_plane(g, pixels, GBUFFER_T),
                       *gnx = filter_gbuffer_plane(g, pixels, GBUFFER_NX),
                       *gny = filter_gbuffer_plane(g, pixels, GBUFFER_NY),
                       *gnz = filter_gbuffer_plane(g, pixels, GBUFFER_NZ);
  const int pixel = y * images->width + x;
  const float px = gx[pixel], py = gy[pixel], pz = gz[pixel];
  const float nx = gnx[pixel], ny = gny[pixel], nz = gnz[pixel];
  const float footprint = filter_gbuffer_plane(g, pixels, GBUFFER_FOOTPRINT)[pixel];
  const float per_plane_distance = 1.0f / (f.sigma_plane * footprint);
  const float value_p = images->ao[pixel];
  const float per_value_difference =
      1.0f / (f.sigma_value * sqrt(blurred_variance(images, x, y, columns_inside)) + 1e-6f);
  const float spline[3] = {6.0f / 16.0f, 4.0f / 16.0f, 1.0f / 16.0f};
  float sum = 0.0f, weights = 0.0f, variance_sum = 0.0f;
#pragma unroll
  for (int dy = -2; dy <= 2; ++dy)
#pragma unroll
    for (int dx = -2; dx <= 2; ++dx) {
      const Tap tap = tap_at(images, x, y, dx * step, dy * step, columns_inside);
      const int q = tap.index;
      const float value_q = images->ao[q];
      const float plane = fabs(nx * (gx[q] - px) + ny * (gy[q] - py) + nz * (gz[q] - pz)) * per_plane_distance;
      const float facing = fmax(0.0f, nx * gnx[q] + ny * gny[q] + nz * gnz[q]);
      const float w = dx == 0 && dy == 0 ? 1.0f
                                         : power(facing, f.sigma_normal) *
                                               exp(-plane - fabs(value_p - value_q) * per_value_difference);
      const float hw = tap.inside && gt[q] > 0.0f ? spline[abs(dx)] * spline[abs(dy)] * w : 0.0f;
      sum += hw * value_q;
      weights += hw;
      variance_sum += hw * hw * images->variance[q];
    }
  const int hit = gt[pixel] > 0.0f;                                  // a miss keeps its value
  ao_out[pixel] = hit ? clamp(sum / weights, 0.0f, 1.0f) : value_p;  // a weighted mean: only rounding leaves [0, 1]
  variance_out[pixel] = hit ? variance_sum / (weights * weights) : images->variance[pixel];
}

#define ATROUS_PARAMS                                                                                               \
  __global const float *gbuffer, __global const float *ao, __global const float *variance, uint width, uint height, \
      uint step, float sigma_plane, uint sigma_normal, float sigma_value, __global float *ao_out,                   \
      __global float *variance_out

#define ATROUS_IMAGES \
  { gbuffer, ao, variance, (int)width, (int)height }
#define ATROUS_WEIGHTS \
  { sigma_plane, sigma_value, sigma_normal }

// Columns [2 step, width - 2 step), one work item for each of their pixels.
__kernel void denoise_atrous_interior(ATROUS_PARAMS) {
  const int border = 2 * (int)step;
  const int x = border + (int)get_global_id(0), y = (int)get_global_id(1);
  if (x >= (int)width - border || y >= (int)height) return;
  const Images images = ATROUS_IMAGES;
  const FilterWeights f = ATROUS_WEIGHTS;
  filter_pixel(&images, f, x, y, (int)step, 1, ao_out, variance_out);
}

// The columns left of the interior and then those right of it, min(4 step,
// width) in all, one work item for each of their pixels, row by row: a grid
// of one dimension, as the strips are too narrow for groups of one row.
__kernel void denoise_atrous_border(ATROUS_PARAMS) {
  const int left = min(2 * (int)step, (int)width), right = max((int)width - 2 * (int)step, left);
  const int columns = min(4 * (int)step, (int)width);
  const int i = (int)(get_global_id(0) % columns), y = (int)(get_global_id(0) / columns);
  const int x = i < left ? i : right + (i - left);
  if (y >= (int)height) return;
  const Images images = ATROUS_IMAGES;
  const FilterWeights f = ATROUS_WEIGHTS;
  filter_pixel(&images, f, x, y, (int)step, 0, ao_out, variance_out);
}
