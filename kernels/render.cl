// Multi-bounce ambient occlusion (SPEC 1-2): camera rays first, then one work
// item per pixel that runs the chosen estimator for each of its camera samples.
#include "mbao/limits.h"
#include "kd_traversal.h"

#ifndef MBAO_UNLIMITED_DISTANCE
#define MBAO_UNLIMITED_DISTANCE 0
#endif
#include "surface.h"
#include "sampling.h"

// Camera rays (SPEC 3.1). One work item per camera sample of the tile; the
// closest hit is stored as (t, triangle, b1, b2) bits.
__kernel void trace_camera_rays(MBAO_SCENE_PARAMS, float4 eye, float4 forward, float4 right,
                                float4 up, float2 film_scale, uint width, uint height, uint spp,
                                uint2 seed, uint first_pixel, uint pixel_count,
                                __global uint4* camera_hits, __global ulong* traversal_totals) {
  const uint sample_index = get_global_id(0);
  if (sample_index >= pixel_count * spp) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  const uint pixel = first_pixel + sample_index / spp;
  const uint camera_sample = sample_index % spp;

  float2 in_pixel = (float2)(0.5f, 0.5f);
  if (spp > 1) {
    const Philox4x32 r = random_block(pixel, camera_sample, 0, 0, seed);
    in_pixel = (float2)(philox_unit_float(r.v[0]), philox_unit_float(r.v[1]));
  }
  const float u = (((float)(pixel % width) + in_pixel.x) / (float)width) * 2.0f - 1.0f;
  const float v = 1.0f - (((float)(pixel / width) + in_pixel.y) / (float)height) * 2.0f;
  const float3 dir = normalize(forward.xyz + u * film_scale.x * right.xyz + v * film_scale.y * up.xyz);

  Hit hit;
  TraversalCounts counts = no_traversal_counts();
  trace_ray(&scene, eye.xyz, dir, INFINITY, 0, &hit, &counts);
  camera_hits[sample_index] = (uint4)(as_uint(hit.t), hit.triangle, as_uint(hit.b1), as_uint(hit.b2));
#if MBAO_COUNT_TRAVERSAL
  add_traversal_counts(traversal_totals, &counts);
#endif
}

typedef struct AoSettings {
  uint bounces;
  uint samples;  // r: directions per hit
  float rho;
  float max_distance;
  uint2 seed;
} AoSettings;

// The settings of a frame. Programs built for max_distance = inf have it as a
// constant (MBAO_UNLIMITED_DISTANCE) and ignore the argument.
static inline AoSettings ao_settings(uint bounces, uint samples, float rho, float max_distance,
                                     uint2 seed) {
  AoSettings s;
  s.bounces = bounces;
  s.samples = samples;
  s.rho = rho;
#if MBAO_UNLIMITED_DISTANCE
  s.max_distance = INFINITY;
#else
  s.max_distance = max_distance;
#endif
  s.seed = seed;
  return s;
}

#define MBAO_RAY_BLOCKED 0  // below the geometric surface: occluded, no bounce
#define MBAO_RAY_ESCAPED 1  // nothing within max_distance
#define MBAO_RAY_HIT 2

// Draws the direction of one AO ray from `from` and traces it. A hit point is
// only needed where the estimator bounces on; elsewhere any hit will do.
static inline int cast_ao_ray(const SceneView* scene, const Surface* from, const AoSettings* s,
                              uint pixel, uint camera_sample, uint bounce, uint node,
                              int need_hit_point, float3* dir, Hit* hit, uint* rays,
                              TraversalCounts* counts) {
  const Philox4x32 r = random_block(pixel, camera_sample, bounce, node, s->seed);
  *dir = cosine_direction(from->shading_normal, philox_unit_float(r.v[0]), philox_unit_float(r.v[1]));
  if (dot(*dir, from->geometric_normal) <= 0.0f) return MBAO_RAY_BLOCKED;
  ++*rays;
  const float3 origin = offset_origin(from, *dir);
  return trace_ray(scene, origin, *dir, s->max_distance, !need_hit_point, hit, counts)
             ? MBAO_RAY_HIT
             : MBAO_RAY_ESCAPED;
}

static inline int bounces_on(const AoSettings* s, uint bounce) {
  return bounce < s->bounces && s->rho > 0.0f;
}

// The paper's estimator: r new directions at every hit of every bounce but the
// last, r + r^2 + ... + r^b rays, walked depth first with one surface per level.
// Every escape at bounce k weighs rho^(k-1) / r^k, so escapes are counted per
// bounce and weighed once at the end: the sum of b + 1 bounces then starts
// with the exact sum of b bounces, and L_b <= L_(b+1) holds sample by sample.
static float branching_estimate(const SceneView* scene, const Surface* primary,
                                const AoSettings* s, uint pixel, uint camera_sample, uint* rays,
                                TraversalCounts* counts) {
  Surface surface[MBAO_MAX_BRANCHING_BOUNCES];
  uint next_child[MBAO_MAX_BRANCHING_BOUNCES];
  uint node[MBAO_MAX_BRANCHING_BOUNCES];
  uint escapes[MBAO_MAX_BRANCHING_BOUNCES];
  for (uint k = 0; k < s->bounces; ++k) escapes[k] = 0;
  surface[0] = *primary;
  next_child[0] = 0;
  node[0] = 0;

  int level = 0;
  while (level >= 0) {
    if (next_child[level] == s->samples) {
      --level;
      continue;
    }
    const uint child = node[level] * s->samples + next_child[level]++;
    const uint bounce = (uint)level + 1;
    const int bounce_on = bounces_on(s, bounce);
    float3 dir;
    Hit hit;
    const int outcome = cast_ao_ray(scene, &surface[level], s, pixel, camera_sample, bounce, child,
                                    bounce_on, &dir, &hit, rays, counts);
    if (outcome == MBAO_RAY_ESCAPED) {
      ++escapes[level];
    } else if (outcome == MBAO_RAY_HIT && bounce_on) {
      ++level;
      surface[level] = make_surface(scene, hit, dir);
      next_child[level] = 0;
      node[level] = child;
    }
  }

  const float inv_samples = 1.0f / (float)s->samples;
  float value = 0.0f, weight = inv_samples;
  for (uint k = 0; k < s->bounces; ++k) {
    value += (float)escapes[k] * weight;
    weight *= s->rho * inv_samples;
  }
  return fmin(value, 1.0f);  // rounding of the weights must not lift it past 1
}

// r paths of up to b segments, one direction per further bounce; an escape at
// bounce k adds rho^(k-1), and the sum is divided by r once.
static float path_estimate(const SceneView* scene, const Surface* primary, const AoSettings* s,
                           uint pixel, uint camera_sample, uint* rays, TraversalCounts* counts) {
  float sum = 0.0f;
  for (uint path = 0; path < s->samples; ++path) {
    Surface surface = *primary;
    float weight = 1.0f;
    for (uint bounce = 1; bounce <= s->bounces; ++bounce) {
      const int bounce_on = bounces_on(s, bounce);
      float3 dir;
      Hit hit;
      const int outcome = cast_ao_ray(scene, &surface, s, pixel, camera_sample, bounce, path,
                                      bounce_on, &dir, &hit, rays, counts);
      if (outcome == MBAO_RAY_ESCAPED) sum += weight;
      if (outcome != MBAO_RAY_HIT || !bounce_on) break;
      surface = make_surface(scene, hit, dir);
      weight *= s->rho;
    }
  }
  return fmin(sum / (float)s->samples, 1.0f);
}

#define MBAO_ESTIMATOR_BRANCHING 0
#define MBAO_ESTIMATOR_PATH 1

// One pixel: the mean over its camera samples of L_b, 1 where the camera ray
// missed; the coverage flag says whether any camera sample hit.
static inline void shade_pixel(const SceneView* scene, int estimator, float4 eye, uint spp,
                               const AoSettings* s, uint first_pixel, uint pixel_index,
                               __global const uint4* camera_hits, __global float* ao,
                               __global uchar* coverage, __global uint* secondary_rays,
                               __global ulong* traversal_totals) {
  const uint pixel = first_pixel + pixel_index;
  float sum = 0.0f;
  uint covered = 0, rays = 0;
  TraversalCounts counts = no_traversal_counts();
  for (uint camera_sample = 0; camera_sample < spp; ++camera_sample) {
    const uint4 bits = camera_hits[pixel_index * spp + camera_sample];
    Hit hit;
    hit.t = as_float(bits.x);
    hit.triangle = bits.y;
    hit.b1 = as_float(bits.z);
    hit.b2 = as_float(bits.w);
    if (hit.triangle == MBAO_NO_TRIANGLE) {
      sum += 1.0f;
      continue;
    }
    covered = 1;
    const float3 p0 = triangle_corner(scene, hit.triangle, 0);
    const float3 p1 = triangle_corner(scene, hit.triangle, 1);
    const float3 p2 = triangle_corner(scene, hit.triangle, 2);
    const float3 hit_point = (1.0f - hit.b1 - hit.b2) * p0 + hit.b1 * p1 + hit.b2 * p2;
    const Surface primary = make_surface(scene, hit, hit_point - eye.xyz);
    sum += estimator == MBAO_ESTIMATOR_BRANCHING
               ? branching_estimate(scene, &primary, s, pixel, camera_sample, &rays, &counts)
               : path_estimate(scene, &primary, s, pixel, camera_sample, &rays, &counts);
  }
  ao[pixel] = sum / (float)spp;
  coverage[pixel] = (uchar)covered;
  secondary_rays[pixel] = rays;
#if MBAO_COUNT_TRAVERSAL
  add_traversal_counts(traversal_totals, &counts);
#endif
}

#define MBAO_AO_KERNEL(name, estimator)                                                          \
  __kernel void name(MBAO_SCENE_PARAMS, float4 eye, uint spp, uint bounces, uint samples,       \
                     float rho, float max_distance, uint2 seed, uint first_pixel,               \
                     uint pixel_count, __global const uint4 *camera_hits, __global float *ao,   \
                     __global uchar *coverage, __global uint *secondary_rays,                   \
                     __global ulong *traversal_totals) {                                        \
    const uint pixel_index = get_global_id(0);                                                   \
    if (pixel_index >= pixel_count) return;                                                      \
    const SceneView scene = MBAO_SCENE_VIEW();                                                   \
    const AoSettings s = ao_settings(bounces, samples, rho, max_distance, seed);                 \
    shade_pixel(&scene, estimator, eye, spp, &s, first_pixel, pixel_index, camera_hits, ao,      \
                coverage, secondary_rays, traversal_totals);                                     \
  }

MBAO_AO_KERNEL(ao_branching, MBAO_ESTIMATOR_BRANCHING)
MBAO_AO_KERNEL(ao_path, MBAO_ESTIMATOR_PATH)
