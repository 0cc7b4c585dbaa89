// Horizon-based ambient occlusion (Bavoil, Sainz and Dimitrov 2008) as SPEC 4
// defines it: the screen-space baseline the ray-traced estimators are compared
// with. It reads the G-buffer (SPEC 7.2) that render.cl's camera rays wrote,
// and walks no tree.
//
// Written for PoCL's vectoriser (see denoise.cl): the G-buffer is read plane
// by plane, view-space points are rebuilt from the depth plane (one load per
// sample), directions come from unit_circle.h rather than sin and cos, a
// sample's pixel is rounded by truncation (PoCL's code for rint, floor or
// convert_int_rte makes the pass slower), and a sample that does not count is
// masked, not skipped. The loops over directions and steps run the same
// number of times in every work item, so a barrier every few steps is legal;
// PoCL cuts the loop body there into a loop over the group's work items of its
// own, which it turns into vector code (a loop whose count is a kernel
// argument would otherwise keep it scalar).
#include "mbao/gbuffer.h"
#include "mbao/unit_circle.h"
#include "sampling.h"

// The steps between barriers, unrolled: fewer barriers, fewer of the values that
// PoCL saves and restores around each, and at most two steps wasted per direction.
#define MBAO_HBAO_STEPS_PER_BARRIER 3u

// Pixel (x, y)'s view-space x and y per unit of depth: x * scale + offset.
typedef struct PixelRays {
  float x_scale, x_offset, y_scale, y_offset;
} PixelRays;

static inline PixelRays pixel_rays(float2 film_scale, uint width, uint height) {
  // camera_ray_direction's u and v times the film scale, for the pixel centres.
  const PixelRays rays = {2.0f * film_scale.x / (float)width, film_scale.x * (1.0f / (float)width - 1.0f),
                          -2.0f * film_scale.y / (float)height, film_scale.y * (1.0f - 1.0f / (float)height)};
  return rays;
}

// Access (1 = open) and coverage per pixel, one work item per pixel on a grid
// of columns x rows. Directions and the first step are jittered per pixel by
// the seed.
__kernel void hbao(__global const float* gbuffer, uint width, uint height, float4 right, float4 up, float4 forward,
                   float2 film_scale, float radius, float sin_bias, float falloff, uint directions, uint steps,
                   uint2 seed, __global float* ao, __global uchar* coverage) {
  // Work items past the image's edge take its last pixel and store nothing: every
  // work item of a group must reach the barriers.
  const uint x = min((uint)get_global_id(0), width - 1), y = min((uint)get_global_id(1), height - 1);
  const uint pixels = width * height, pixel = y * width + x;
  const __global float* depths = hbao_gbuffer_plane(gbuffer, pixels, GBUFFER_DEPTH);
  const float depth = depths[pixel];
  const float sx = hbao_gbuffer_plane(gbuffer, pixels, GBUFFER_SX)[pixel];
  const float sy = hbao_gbuffer_plane(gbuffer, pixels, GBUFFER_SY)[pixel];
  const float sz = hbao_gbuffer_plane(gbuffer, pixels, GBUFFER_SZ)[pixel];
  // The shading normal in view space.
  const float nx = sx * right.x + sy * right.y + sz * right.z;
  const float ny = sx * up.x + sy * up.y + sz * up.z;
  const float nz = sx * forward.x + sy * forward.y + sz * forward.z;
  const PixelRays rays = pixel_rays(film_scale, width, height);
  const float px = ((float)x * rays.x_scale + rays.x_offset) * depth;
  const float py = ((float)y * rays.y_scale + rays.y_offset) * depth;
  // The radius as seen at this depth, in pixels, split into steps.
  const float radius_pixels = radius / (depth * film_scale.y) * (0.5f * (float)height);
  const float step_pixels = radius_pixels / (float)(steps + 1);
  const Philox4x32 r = random_block(pixel, 0, 0, 0, seed);
  const float rotation = philox_unit_float(r.v[0]);
  const float first_step = 1.0f + philox_unit_float(r.v[1]);
  const float per_radius2 = 1.0f / (radius * radius);
  float occlusion = 0.0f;
  for (uint i = 0; i < directions; ++i) {
    const UnitCirclePoint direction = unit_circle_point(2.0f * M_PI_F * ((float)i + rotation) / (float)directions);
    // One step in the image; its rows grow downward, view y upward.
    const float step_x = step_pixels * direction.c, step_y = -step_pixels * direction.s;
    float sin_horizon = sin_bias;
    for (uint first = 0; first < steps; first += MBAO_HBAO_STEPS_PER_BARRIER) {
      MBAO_UNROLL
      for (uint j = 0; j < MBAO_HBAO_STEPS_PER_BARRIER; ++j) {
        const uint k = first + j;
        const float along = first_step + (float)k;
        // The nearest pixel (SPEC 4), halves rounded up: truncating x + 1/2 rounds so
        // where that lies on the image, the only place it is read. Whether it does is
        // decided in floats, which also holds where the step is infinite or NaN.
        const float round_x = (float)x + along * step_x + 0.5f, round_y = (float)y + along * step_y + 0.5f;
        const int at_x = convert_int(round_x), at_y = convert_int(round_y);
        // Once a direction's steps leave the image they stay out: masked, as the end of the direction.
        const int inside =
            k < steps && round_x >= 0.0f && round_x < (float)width && round_y >= 0.0f && round_y < (float)height;
        const float seen_depth = depths[inside ? at_y * (int)width + at_x : (int)pixel];
        const float dx = ((float)at_x * rays.x_scale + rays.x_offset) * seen_depth - px;
        const float dy = ((float)at_y * rays.y_scale + rays.y_offset) * seen_depth - py;
        const float dz = seen_depth - depth;
        const float d2 = dx * dx + dy * dy + dz * dz;
        const float r2 = d2 * per_radius2;
        const float sin_sample = (dx * nx + dy * ny + dz * nz) * rsqrt(d2);
        // Missed pixels have depth 0. A step that lands on the pixel itself is no
        // sample: compared by position, as its rebuilt point may be off its own by
        // rounding (contracted into fused multiply-adds or not), with any slope.
        const int elsewhere = at_x != (int)x || at_y != (int)y;
        const int rises = inside && elsewhere && seen_depth > 0.0f && r2 <= 1.0f && sin_sample > sin_horizon;
        occlusion += rises ? (1.0f - falloff * r2) * (sin_sample - sin_horizon) : 0.0f;
        sin_horizon = rises ? sin_sample : sin_horizon;
      }
      barrier(CLK_LOCAL_MEM_FENCE);
    }
  }
  if (get_global_id(0) >= width || get_global_id(1) >= height) return;
  const int hit = depth > 0.0f;
  coverage[pixel] = hit ? 255 : 0;
  // Below half a pixel per step every sample lands on the pixel itself: nothing to see.
  ao[pixel] = hit && step_pixels >= 0.5f ? clamp(1.0f - occlusion / (float)directions, 0.0f, 1.0f) : 1.0f;
}
