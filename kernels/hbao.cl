// Horizon-based ambient occlusion (Bavoil, Sainz and Dimitrov 2008) on the
// depth and normals of the primary hits (SPEC 4): the screen-space baseline
// the ray-traced estimators are compared with. First a G-buffer pass traces
// the camera ray through every pixel centre, then each pixel marches the
// G-buffer along a few image directions and integrates the horizon it finds.
#include "kd_traversal.h"
#include "surface.h"
#include "sampling.h"
#include "camera.h"
#include "mbao/pixel_order.h"

// View space: x right, y up, z the depth along the view direction.
static inline float3 to_view(float3 v, float3 forward, float3 right, float3 up) {
  return (float3)(dot(v, right), dot(v, up), dot(v, forward));
}

// Per pixel the view-space hit point (.w = 1; 0 where the ray missed) and the
// view-space shading normal, turned toward the camera.
__kernel void hbao_gbuffer(MBAO_SCENE_PARAMS, float4 eye, float4 forward, float4 right, float4 up,
                           float2 film_scale, uint width, uint height, __global float4* positions,
                           __global float4* normals) {
  const uint position = get_global_id(0);
  if (position >= width * height) return;
  const uint pixel = pixel_at_position(position, width, height);
  const SceneView scene = MBAO_SCENE_VIEW();
  const float3 dir = camera_ray_direction(forward.xyz, right.xyz, up.xyz, film_scale, width, height, pixel,
                                          (float2)(0.5f, 0.5f));
  Hit hit;
  TraversalCounts counts = no_traversal_counts();
  if (!trace_ray(&scene, eye.xyz, dir, INFINITY, 0, &hit, &counts)) {
    positions[pixel] = (float4)(0.0f);
    normals[pixel] = (float4)(0.0f);
    return;
  }
  const Surface s = make_surface(&scene, hit, dir);
  positions[pixel] = (float4)(to_view(s.position - eye.xyz, forward.xyz, right.xyz, up.xyz), 1.0f);
  normals[pixel] = (float4)(to_view(s.shading_normal, forward.xyz, right.xyz, up.xyz), 0.0f);
}

typedef struct HbaoParams {
  float radius;       // world units
  float sin_bias;     // sine of the angle bias: lower horizons are ignored
  float falloff;      // W(r) = 1 - falloff * r^2 / radius^2
  uint directions, steps;
} HbaoParams;

// The occlusion found along one image direction: Bavoil et al.'s sum of
// attenuated rises of the horizon. Elevations are measured from the tangent
// plane rather than the image plane, so that no flat surface occludes itself
// whatever the perspective (samples snap to pixels and so leave the image-plane
// slice); the horizon starts at the angle bias.
static inline float march_direction(__global const float4* positions, uint width, uint height, int2 from,
                                    float3 p, float3 n, float2 direction, float step_pixels, float first_step,
                                    const HbaoParams* h) {
  float sin_horizon = h->sin_bias;
  float occlusion = 0.0f;
  for (uint k = 0; k < h->steps; ++k) {
    const float2 offset = (first_step + (float)k) * step_pixels * direction;
    // Image rows grow downward, view y upward.
    const int2 at = from + (int2)((int)round(offset.x), -(int)round(offset.y));
    if (at.x < 0 || at.y < 0 || at.x >= (int)width || at.y >= (int)height) break;
    const float4 seen = positions[(uint)at.y * width + (uint)at.x];
    if (seen.w == 0.0f) continue;
    const float3 d = seen.xyz - p;
    const float r2 = dot(d, d) / (h->radius * h->radius);
    if (r2 > 1.0f || r2 == 0.0f) continue;
    const float sin_sample = dot(d, n) * rsqrt(dot(d, d));
    if (sin_sample > sin_horizon) {
      occlusion += (1.0f - h->falloff * r2) * (sin_sample - sin_horizon);
      sin_horizon = sin_sample;
    }
  }
  return occlusion;
}

// Access (1 = open) per pixel; 1 and coverage 0 where the camera ray missed.
// Directions and the first step are jittered per pixel by the seed.
__kernel void hbao(__global const float4* positions, __global const float4* normals, uint width, uint height,
                   float film_scale_y, float radius, float sin_bias, float falloff, uint directions, uint steps,
                   uint2 seed, __global float* ao, __global uchar* coverage) {
  const uint position = get_global_id(0);
  if (position >= width * height) return;
  const uint pixel = pixel_at_position(position, width, height);
  const float4 here = positions[pixel];
  coverage[pixel] = here.w != 0.0f ? 255 : 0;
  if (here.w == 0.0f) {
    ao[pixel] = 1.0f;
    return;
  }
  const HbaoParams h = {radius, sin_bias, falloff, directions, steps};
  // The radius as seen at this depth, in pixels, split into steps.
  const float radius_pixels = radius / (here.z * film_scale_y) * (0.5f * (float)height);
  const float step_pixels = radius_pixels / (float)(steps + 1);
  const Philox4x32 r = random_block(pixel, 0, 0, 0, seed);
  const float rotation = philox_unit_float(r.v[0]);
  const float first_step = 1.0f + philox_unit_float(r.v[1]);
  const int2 from = (int2)((int)(pixel % width), (int)(pixel / width));
  float occlusion = 0.0f;
  if (step_pixels >= 0.5f) {  // else every step lands on this pixel: nothing to see
    for (uint i = 0; i < directions; ++i) {
      float cos_angle;
      const float sin_angle = sincos(2.0f * M_PI_F * ((float)i + rotation) / (float)directions, &cos_angle);
      occlusion += march_direction(positions, width, height, from, here.xyz, normals[pixel].xyz,
                                   (float2)(cos_angle, sin_angle), step_pixels, first_step, &h);
    }
  }
  ao[pixel] = clamp(1.0f - occlusion / (float)directions, 0.0f, 1.0f);
}
