// The estimators of SPEC 2 at the camera hits, and the megakernel that runs
// them one work item per pixel.
#ifndef MBAO_RENDER_AO_ESTIMATORS_H
#define MBAO_RENDER_AO_ESTIMATORS_H

#include "mbao/param_groups.h"
#include "mbao/limits.h"
#include "mbao/pixel_order.h"
#include "kd_packet.h"
#include "surface.h"
#include "sampling.h"
#include "render/camera_rays.h"  // the camera hits the estimators start from

// The settings of a frame that the estimators read: those of MBAO_AO_PARAMS
// but the eye and spp, which the kernels read themselves.
typedef struct AoSettings {
  uint2 image_size;
  uint bounces;
  uint samples;
  float rho;
  float max_distance;
  uint2 seed;
  uint direction_moments;
} AoSettings;

// A kernel's AoSettings from its MBAO_AO_PARAMS.
#define MBAO_AO_SETTINGS() ((AoSettings){image_size, bounces, samples, rho, max_distance, seed, direction_moments})

// The pixel at `index` of the tile that starts at `first_position` of the pixel order.
static inline uint tile_pixel(const AoSettings* s, uint first_position, uint index) {
  return pixel_at_position(first_position + index, s->image_size.x, s->image_size.y);
}

#define MBAO_RAY_BLOCKED 0  // along the geometric surface: occluded, no bounce
#define MBAO_RAY_ESCAPED 1  // nothing within max_distance
#define MBAO_RAY_HIT 2

// Where the `rays` rays leaving `from` start: located in the tree once for
// them all where more than one leaves.
static inline void origin_of_rays(const SceneView* scene, const Surface* from, uint rays, RayOrigin* origin) {
  if (rays > 1)
    locate_ray_origin(scene, leaving_point(from), origin);
  else
    set_ray_origin(leaving_point(from), origin);
}

// A direction drawn around the shading normal that points below the geometric
// surface, mirrored in it (SPEC 3.3): a convex mesh's smooth normals must not
// send rays into the mesh. Returns whether it leaves the surface, which only
// one along the surface (measure zero, or rounding) does not.
static inline int mirrored_above(float3 geometric_normal, float3* dir) {
  const float along = dot(*dir, geometric_normal);
  if (along < 0.0f) *dir -= 2.0f * along * geometric_normal;
  return dot(*dir, geometric_normal) > 0.0f;
}

// Draws the direction of the AO ray at `node` of the estimator's tree from
// `from`: returns 0 where it runs along the geometric surface (blocked).
static inline int ao_ray_direction(const Surface* from, const AoSettings* s, uint pixel, uint camera_sample,
                                   uint bounce, uint node, float3* dir) {
  const Philox4x32 r = random_block(pixel, camera_sample, bounce, node, s->seed);
  *dir = cosine_direction(from->shading_normal, philox_unit_float(r.v[0]), philox_unit_float(r.v[1]));
  return mirrored_above(from->geometric_normal, dir);
}

// ao_ray_direction for the nodes node .. node + 3, drawn together on vectors:
// the same directions and the same verdicts, bit for bit.
static inline void ao_ray_directions_x4(const Surface* from, const AoSettings* s, uint pixel, uint camera_sample,
                                        uint bounce, uint node, float3 dir[4], int cast[4]) {
  uint4 bits[4];
  random_blocks_x4(pixel, camera_sample, bounce, node, s->seed, bits);
  float4 x, y, z;
  cosine_directions_x4(from->shading_normal, philox_unit_floats(bits[0]), philox_unit_floats(bits[1]), &x, &y, &z);
  dir[0] = (float3)(x.s0, y.s0, z.s0);
  dir[1] = (float3)(x.s1, y.s1, z.s1);
  dir[2] = (float3)(x.s2, y.s2, z.s2);
  dir[3] = (float3)(x.s3, y.s3, z.s3);
  for (uint j = 0; j < 4; ++j) cast[j] = mirrored_above(from->geometric_normal, &dir[j]);
}

// Draws the direction of one AO ray from `from` and traces it from `origin`,
// where its rays start. A hit point is only needed where the estimator bounces
// on; elsewhere any hit will do.
static inline int cast_ao_ray(const SceneView* scene, const Surface* from, const RayOrigin* origin, const AoSettings* s,
                              uint pixel, uint camera_sample, uint bounce, uint node, int need_hit_point, float3* dir,
                              Hit* hit, uint* rays, TraversalCounts* counts) {
  if (!ao_ray_direction(from, s, pixel, camera_sample, bounce, node, dir)) return MBAO_RAY_BLOCKED;
  ++*rays;
  return trace_ray_from(scene, origin, *dir, s->max_distance, !need_hit_point, hit, counts) ? MBAO_RAY_HIT
                                                                                            : MBAO_RAY_ESCAPED;
}

static inline int bounces_on(const AoSettings* s, uint bounce) { return bounce < s->bounces && s->rho > 0.0f; }

// The value of one camera sample from its escapes per bounce: every escape
// at bounce k weighs rho^(k-1) / r^k. Both organisations end here, so their
// images agree bit for bit.
static float branching_value(const uint* escapes, const AoSettings* s) {
  const float inv_samples = 1.0f / (float)s->samples;
  float value = 0.0f, weight = inv_samples;
  for (uint k = 0; k < s->bounces; ++k) {
    value += (float)escapes[k] * weight;
    weight *= s->rho * inv_samples;
  }
  return fmin(value, 1.0f);  // rounding of the weights must not lift it past 1
}

// The sum and the sum of squares of the values of the r directions drawn at a
// primary hit (SPEC 7.1).
typedef struct DirectionMoments {
  float sum, squares;
} DirectionMoments;

static inline void add_direction_value(float value, DirectionMoments* m) {
  m->sum += value;
  m->squares += value * value;
}

// The value of one direction drawn at the primary hit, from the escapes per
// bounce of its subtree of the branching estimator: an escape at bounce k + 1
// weighs (rho / r)^k.
static inline float direction_value(const uint* escapes, const AoSettings* s) {
  float value = 0.0f, weight = 1.0f;
  for (uint k = 0; k < s->bounces; ++k) {
    value += (float)escapes[k] * weight;
    weight *= s->rho / (float)s->samples;
  }
  return value;
}

// Adds the value of the subtree walked since `before` was taken, and takes it anew.
static inline void end_direction(const uint* escapes, uint* before, const AoSettings* s, DirectionMoments* m) {
  uint subtree[MBAO_MAX_BRANCHING_BOUNCES];
  for (uint k = 0; k < s->bounces; ++k) {
    subtree[k] = escapes[k] - before[k];
    before[k] = escapes[k];
  }
  add_direction_value(direction_value(subtree, s), m);
}

// The paper's estimator: r new directions at every hit of every bounce but the
// last, r + r^2 + ... + r^b rays, walked depth first with one surface per level.
// Escapes are counted per bounce and weighed once at the end: the sum of b + 1
// bounces then starts with the exact sum of b bounces, and L_b <= L_(b+1)
// holds sample by sample.
static float branching_estimate(const SceneView* scene, const Surface* primary, const AoSettings* s, uint pixel,
                                uint camera_sample, uint* rays, TraversalCounts* counts, DirectionMoments* moments) {
  Surface surface[MBAO_MAX_BRANCHING_BOUNCES];
  RayOrigin origin[MBAO_MAX_BRANCHING_BOUNCES];
  uint next_child[MBAO_MAX_BRANCHING_BOUNCES];
  uint node[MBAO_MAX_BRANCHING_BOUNCES];
  uint escapes[MBAO_MAX_BRANCHING_BOUNCES];
  for (uint k = 0; k < s->bounces; ++k) escapes[k] = 0;
  uint before[MBAO_MAX_BRANCHING_BOUNCES];  // direction moments only
  for (uint k = 0; k < s->bounces; ++k) before[k] = 0;
  surface[0] = *primary;
  origin_of_rays(scene, primary, s->samples, &origin[0]);
  next_child[0] = 0;
  node[0] = 0;

  int level = 0;
  while (level >= 0) {
    if (next_child[level] == s->samples) {
      --level;
      continue;
    }
    if (s->direction_moments && level == 0 && next_child[0] > 0) end_direction(escapes, before, s, moments);
    const uint child = node[level] * s->samples + next_child[level]++;
    const uint bounce = (uint)level + 1;
    const int bounce_on = bounces_on(s, bounce);
    float3 dir;
    Hit hit;
    const int outcome = cast_ao_ray(scene, &surface[level], &origin[level], s, pixel, camera_sample, bounce, child,
                                    bounce_on, &dir, &hit, rays, counts);
    if (outcome == MBAO_RAY_ESCAPED) {
      ++escapes[level];
    } else if (outcome == MBAO_RAY_HIT && bounce_on) {
      ++level;
      surface[level] = make_surface(scene, hit, dir);
      origin_of_rays(scene, &surface[level], s->samples, &origin[level]);
      next_child[level] = 0;
      node[level] = child;
    }
  }
  if (s->direction_moments) end_direction(escapes, before, s, moments);
  return branching_value(escapes, s);
}

// r paths of up to b segments, one direction per further bounce; an escape at
// bounce k adds rho^(k-1), and the sum is divided by r once.
static float path_estimate(const SceneView* scene, const Surface* primary, const AoSettings* s, uint pixel,
                           uint camera_sample, uint* rays, TraversalCounts* counts, DirectionMoments* moments) {
  RayOrigin primary_origin, origin;
  origin_of_rays(scene, primary, s->samples, &primary_origin);
  float sum = 0.0f;
  for (uint path = 0; path < s->samples; ++path) {
    Surface surface = *primary;
    const RayOrigin* from = &primary_origin;
    float weight = 1.0f;
    for (uint bounce = 1; bounce <= s->bounces; ++bounce) {
      const int bounce_on = bounces_on(s, bounce);
      float3 dir;
      Hit hit;
      const int outcome = cast_ao_ray(scene, &surface, from, s, pixel, camera_sample, bounce, path, bounce_on, &dir,
                                      &hit, rays, counts);
      if (outcome == MBAO_RAY_ESCAPED) {
        sum += weight;
        // A path escapes once, where it ends; one that does not adds 0.
        if (s->direction_moments) add_direction_value(weight, moments);
      }
      if (outcome != MBAO_RAY_HIT || !bounce_on) break;
      surface = make_surface(scene, hit, dir);
      origin_of_rays(scene, &surface, 1, &origin);
      from = &origin;
      weight *= s->rho;
    }
  }
  return fmin(sum / (float)s->samples, 1.0f);
}

// A pixel's variance (SPEC 7.1): the spread of its camera samples' values
// where it has two or more, else of its one sample's r direction values.
static inline float pixel_variance(float sum, float sum_of_squares, uint spp, DirectionMoments directions, uint r) {
  const float n = (float)(spp > 1 ? spp : r);
  const float total = spp > 1 ? sum : directions.sum;
  const float squares = spp > 1 ? sum_of_squares : directions.squares;
  return fmax(0.0f, squares - total * total / n) / ((n - 1.0f) * n);
}

// A pixel from the sum of its camera samples' values (1 for each that missed)
// and the number of them that hit: its coverage in 255ths, rounded up (SPEC 2).
// Where ao_second_moment is given, the mean of the values' squares too: a
// bake's standard errors come from it (SPEC 6.4); where ao_variance is, the
// pixel's variance.
static inline void store_pixel(uint pixel, float sum, float sum_of_squares, DirectionMoments directions, uint spp,
                               uint r, uint covered, uint rays, __global float* ao, __global float* ao_second_moment,
                               __global float* ao_variance, __global uchar* coverage, __global uint* secondary_rays) {
  ao[pixel] = sum / (float)spp;
  if (ao_second_moment) ao_second_moment[pixel] = sum_of_squares / (float)spp;
  if (ao_variance) ao_variance[pixel] = pixel_variance(sum, sum_of_squares, spp, directions, r);
  coverage[pixel] = (uchar)((covered * 255u + spp - 1u) / spp);
  secondary_rays[pixel] = rays;
}

#define MBAO_ESTIMATOR_BRANCHING 0
#define MBAO_ESTIMATOR_PATH 1

// One pixel: the mean over its camera samples of L_b, 1 where the camera ray
// missed, and its coverage.
static inline void shade_pixel(const SceneView* scene, int estimator, float4 eye, uint spp, const AoSettings* s,
                               uint first_position, uint pixel_index, __global const uint4* camera_hits,
                               __global float* ao, __global float* ao_second_moment, __global float* ao_variance,
                               __global uchar* coverage, __global uint* secondary_rays,
                               __global ulong* traversal_totals) {
  const uint pixel = tile_pixel(s, first_position, pixel_index);
  float sum = 0.0f, sum_of_squares = 0.0f;
  DirectionMoments directions = {0.0f, 0.0f};  // kept at spp = 1 only
  uint covered = 0, rays = 0;
  TraversalCounts counts = no_traversal_counts();
  for (uint camera_sample = 0; camera_sample < spp; ++camera_sample) {
    const Hit hit = stored_hit(camera_hits, pixel_index * spp + camera_sample);
    float value = 1.0f;
    if (hit.triangle != MBAO_NO_TRIANGLE) {
      ++covered;
      const Surface primary = primary_surface(scene, hit, eye);
      value = estimator == MBAO_ESTIMATOR_BRANCHING
                  ? branching_estimate(scene, &primary, s, pixel, camera_sample, &rays, &counts, &directions)
                  : path_estimate(scene, &primary, s, pixel, camera_sample, &rays, &counts, &directions);
    }
    sum += value;
    sum_of_squares += value * value;
  }
  store_pixel(pixel, sum, sum_of_squares, directions, spp, s->samples, covered, rays, ao, ao_second_moment, ao_variance,
              coverage, secondary_rays);
  add_traversal_counts(traversal_totals, &counts);
}

// The megakernel: one work item per pixel runs the whole estimator.
#define MBAO_AO_KERNEL(name, estimator)                                                                          \
  __kernel void name(MBAO_SCENE_PARAMS, MBAO_AO_PARAMS uint first_position, uint pixel_count,                    \
                     __global const uint4* camera_hits, __global float* ao, __global float* ao_second_moment,    \
                     __global float* ao_variance, __global uchar* coverage, __global uint* secondary_rays,       \
                     __global ulong* traversal_totals) {                                                         \
    const uint pixel_index = get_global_id(0);                                                                   \
    if (pixel_index >= pixel_count) return;                                                                      \
    const SceneView scene = MBAO_SCENE_VIEW();                                                                   \
    const AoSettings s = MBAO_AO_SETTINGS();                                                                     \
    shade_pixel(&scene, estimator, eye, spp, &s, first_position, pixel_index, camera_hits, ao, ao_second_moment, \
                ao_variance, coverage, secondary_rays, traversal_totals);                                        \
  }

MBAO_AO_KERNEL(ao_branching, MBAO_ESTIMATOR_BRANCHING)
MBAO_AO_KERNEL(ao_path, MBAO_ESTIMATOR_PATH)

#endif
