// Temporal accumulation (SPEC 7.4): each pixel's value and variance blended
// with the history of the frames before, reprojected from the last one's
// camera through the G-buffers. One work item per pixel.
#include "camera.h"
#include "mbao/gbuffer.h"
#include "mbao/param_groups.h"

// One pixel's G-buffer entry: its point, its normal and its footprint; t > 0 where it hit.
typedef struct Surfel {
  float3 point, normal;
  float t, footprint;
} Surfel;

static inline Surfel surfel_at(const __global float* gbuffer, uint pixels, uint pixel) {
  const Surfel s = {(float3)(filter_gbuffer_plane(gbuffer, pixels, GBUFFER_X)[pixel],
                             filter_gbuffer_plane(gbuffer, pixels, GBUFFER_Y)[pixel],
                             filter_gbuffer_plane(gbuffer, pixels, GBUFFER_Z)[pixel]),
                    (float3)(filter_gbuffer_plane(gbuffer, pixels, GBUFFER_NX)[pixel],
                             filter_gbuffer_plane(gbuffer, pixels, GBUFFER_NY)[pixel],
                             filter_gbuffer_plane(gbuffer, pixels, GBUFFER_NZ)[pixel]),
                    filter_gbuffer_plane(gbuffer, pixels, GBUFFER_T)[pixel],
                    filter_gbuffer_plane(gbuffer, pixels, GBUFFER_FOOTPRINT)[pixel]};
  return s;
}

// Whether the previous frame's pixel `tap` saw the surface that `p` sees: it
// hit, p's point lies within 2 of its footprints of its tangent plane, and
// their normals are within about 26 degrees.
static inline int same_surface(Surfel tap, Surfel p) {
  return tap.t > 0.0f && fabs(dot(tap.normal, p.point - tap.point)) <= 2.0f * tap.footprint &&
         dot(tap.normal, p.normal) >= 0.9f;
}

// The history a pixel takes from the frame before: the weighted means of its
// valid taps' accumulated value, variance and history length.
typedef struct Reprojected {
  float value, variance, length, weight;  // weight 0: no valid tap (a disocclusion)
} Reprojected;

typedef struct PreviousFrame {
  const __global float *gbuffer, *ao, *variance;
  const __global uint* length;
  float3 eye, forward, right, up;
  float2 film_scale;
  uint width, height;
} PreviousFrame;

static inline Reprojected reproject(const PreviousFrame* previous, Surfel p) {
  Reprojected r = {0.0f, 0.0f, 0.0f, 0.0f};
  const float3 at = camera_image_position(previous->forward, previous->right, previous->up, previous->film_scale,
                                          previous->width, previous->height, p.point - previous->eye);
  if (!(at.z > 0.0f)) return r;
  // Within 1e-2 pixels of a pixel centre, that pixel alone: a still camera
  // reprojects exactly, whatever the rounding of the hit points.
  const float2 nearest = round(at.xy);
  const int snap = fabs(at.x - nearest.x) <= 1e-2f && fabs(at.y - nearest.y) <= 1e-2f;
  const float2 corner = snap ? nearest : floor(at.xy), fraction = snap ? (float2)(0.0f) : at.xy - corner;
  const uint pixels = previous->width * previous->height;
  for (int j = 0; j < 4; ++j) {
    const int dx = j & 1, dy = j >> 1;
    const float w = (dx ? fraction.x : 1.0f - fraction.x) * (dy ? fraction.y : 1.0f - fraction.y);
    const int x = (int)corner.x + dx, y = (int)corner.y + dy;
    if (w == 0.0f || x < 0 || y < 0 || x >= (int)previous->width || y >= (int)previous->height) continue;
    const uint tap = (uint)y * previous->width + (uint)x;
    if (!same_surface(surfel_at(previous->gbuffer, pixels, tap), p)) continue;
    r.value += w * previous->ao[tap];
    r.variance += w * previous->variance[tap];
    r.length += w * (float)previous->length[tap];
    r.weight += w;
  }
  if (r.weight > 0.0f) {
    r.value /= r.weight;
    r.variance /= r.weight;
    r.length /= r.weight;
  }
  return r;
}

// ao and variance: the frame's render and its variance in, the accumulated
// value and its variance out; next_*: the same for the history, with each
// pixel's history length (0 where it missed). The camera is the last frame's,
// which previous_gbuffer was seen from (both frames are width x height).
__kernel void temporal_accumulate(__global const float* gbuffer, __global float* ao, __global float* variance,
                                  uint has_history, __global const float* previous_gbuffer,
                                  __global const float* previous_ao, __global const float* previous_variance,
                                  __global const uint* previous_length, MBAO_CAMERA_PARAMS uint max_length,
                                  __global float* next_ao, __global float* next_variance, __global uint* next_length) {
  const uint pixel = get_global_id(0), pixels = width * height;
  if (pixel >= pixels) return;
  const Surfel p = surfel_at(gbuffer, pixels, pixel);
  const float c = ao[pixel], v = variance[pixel];
  float a = c, u = v;
  uint n = p.t > 0.0f ? 1u : 0u;
  if (has_history && n) {
    const PreviousFrame previous = {
        previous_gbuffer, previous_ao, previous_variance, previous_length, eye.xyz, forward.xyz,
        right.xyz,        up.xyz,      film_scale,        width,           height};
    const Reprojected history = reproject(&previous, p);
    if (history.weight > 0.0f) {
      n = min((uint)history.length + 1u, max_length);
      const float share = 1.0f / (float)n;
      a = history.value + (c - history.value) * share;
      u = (1.0f - share) * (1.0f - share) * history.variance + v * share * share;
    }
  }
  ao[pixel] = next_ao[pixel] = a;
  variance[pixel] = next_variance[pixel] = u;
  next_length[pixel] = n;
}
