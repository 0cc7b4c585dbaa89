// Multi-bounce ambient occlusion (SPEC 1-2): camera rays first, then either one
// work item per pixel that runs the chosen estimator for each of its camera
// samples (the megakernel) or, for the branching estimator, one launch per
// bounce over the surfaces still bouncing (the wavefront, at the end).
#include "mbao/param_groups.h"
#include "mbao/limits.h"
#include "kd_packet.h"
#include "surface.h"
#include "sampling.h"
#include "camera.h"
#include "mbao/wavefront.h"
#include "mbao/gbuffer.h"
#include "mbao/pixel_order.h"

static inline Hit stored_hit(__global const uint4* hits, uint index) { return hit_of_bits(hits[index]); }

// A camera hit, seen from the eye; with eye.w = 1 a bake's point, given
// instead of traced, on its triangle's front side (SPEC 6.1).
static inline Surface primary_surface(const SceneView* scene, Hit hit, float4 eye) {
  const float3 p0 = triangle_corner(scene, hit.triangle, 0);
  const float3 p1 = triangle_corner(scene, hit.triangle, 1);
  const float3 p2 = triangle_corner(scene, hit.triangle, 2);
  if (eye.w != 0.0f) return make_surface(scene, hit, cross(p2 - p0, p1 - p0));
  const float3 hit_point = (1.0f - hit.b1 - hit.b2) * p0 + hit.b1 * p1 + hit.b2 * p2;
  return make_surface(scene, hit, hit_point - eye.xyz);
}

// Pixel `pixel`'s texel of the G-buffer (SPEC 7.2), from its camera hit
// through the pixel centre: the planes that `planes` names.
static inline void store_gbuffer_texel(const SceneView* scene, Hit hit, float4 eye, float4 forward,
                                       uint2 image_size, float film_scale_y, uint pixel, __global float* gbuffer,
                                       uint planes) {
  GBufferTexel g = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, MBAO_GBUFFER_NO_TRIANGLE};
  if (hit.triangle != MBAO_NO_TRIANGLE) {
    const Surface s = primary_surface(scene, hit, eye);
    g.x = s.position.x;
    g.y = s.position.y;
    g.z = s.position.z;
    g.t = hit.t;
    g.nx = s.geometric_normal.x;
    g.ny = s.geometric_normal.y;
    g.nz = s.geometric_normal.z;
    g.footprint = 2.0f * hit.t * film_scale_y / (float)image_size.y;
    g.depth = dot(s.position - eye.xyz, forward.xyz);
    g.sx = s.shading_normal.x;
    g.sy = s.shading_normal.y;
    g.sz = s.shading_normal.z;
    g.triangle = hit.triangle;
  }
  gbuffer_store(gbuffer, image_size.x * image_size.y, pixel, g, planes);
}

// The direction of camera sample `sample_index` of the positions from
// first_position of the pixel order (mbao/pixel_order.h): spp samples per pixel.
static inline float3 camera_sample_direction(float4 forward, float4 right, float4 up, float2 film_scale, uint width,
                                             uint height, uint spp, uint2 seed, uint first_position,
                                             uint sample_index) {
  const uint pixel = pixel_at_position(first_position + sample_index / spp, width, height);
  const uint camera_sample = sample_index % spp;
  float2 in_pixel = (float2)(0.5f, 0.5f);
  if (spp > 1) {
    const Philox4x32 r = random_block(pixel, camera_sample, 0, 0, seed);
    in_pixel = (float2)(philox_unit_float(r.v[0]), philox_unit_float(r.v[1]));
  }
  return camera_ray_direction(forward.xyz, right.xyz, up.xyz, film_scale, width, height, pixel, in_pixel);
}

// Camera rays (SPEC 3.1). One work item per camera sample of the tile, the
// positions [first_position, first_position + pixel_count); the closest hit is
// stored as (t, triangle, b1, b2) bits where `camera_hits` is given (a frame
// with no AO passes none: it reads the G-buffer alone). Where `gbuffer` is
// given (at spp = 1: the rays through the pixel centres) the pass also writes
// the planes of its texels that `gbuffer_planes` names: one G-buffer pass for
// every screen-space pass and the AO's primary hits.
// The parameters of either kernel of camera rays, one per sample or in packets.
#define MBAO_CAMERA_RAY_PARAMS                                                                              \
  MBAO_SCENE_PARAMS, MBAO_CAMERA_PARAMS uint spp, uint2 seed, uint first_position, uint pixel_count,        \
      __global uint4 *camera_hits, __global ulong *traversal_totals, __global float *gbuffer, uint gbuffer_planes

__kernel void trace_camera_rays(MBAO_CAMERA_RAY_PARAMS) {
  const uint sample_index = get_global_id(0);
  if (sample_index >= pixel_count * spp) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  const float3 dir = camera_sample_direction(forward, right, up, film_scale, width, height, spp, seed,
                                             first_position, sample_index);
  Hit hit;
  TraversalCounts counts = no_traversal_counts();
  trace_ray(&scene, eye.xyz, dir, INFINITY, 0, &hit, &counts);
  if (camera_hits) camera_hits[sample_index] = bits_of_hit(hit);
  if (gbuffer)
    store_gbuffer_texel(&scene, hit, eye, forward, (uint2)(width, height), film_scale.y,
                        pixel_at_position(first_position + sample_index, width, height), gbuffer, gbuffer_planes);
  add_traversal_counts(traversal_totals, &counts);
}

#if MBAO_TRAVERSAL == MBAO_TRAVERSAL_LANES
// trace_camera_rays in packets (kd_packet.h): work item j takes camera samples
// [16 j, 16 j + 16), where spp is 1 a 4 x 4 square of pixels (but in the blocks
// that the image's edges cut), and stores the same hits, counts and texels.
__kernel void trace_camera_packets(MBAO_CAMERA_RAY_PARAMS) {
  const uint first_sample = get_global_id(0) * MBAO_LANES, samples = pixel_count * spp;
  if (first_sample >= samples) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  float dir_x[MBAO_LANES], dir_y[MBAO_LANES], dir_z[MBAO_LANES];
  const uint lanes = min(samples - first_sample, (uint)MBAO_LANES);
  for (uint k = 0; k < lanes; ++k) {
    const float3 dir = camera_sample_direction(forward, right, up, film_scale, width, height, spp, seed,
                                               first_position, first_sample + k);
    dir_x[k] = dir.x;
    dir_y[k] = dir.y;
    dir_z[k] = dir.z;
  }
  uint4 hits[MBAO_LANES];
  PacketCounts counts = {(uint16)(0u), (uint16)(0u), (uint16)(0u)};
  trace_packet(&scene, eye.xyz, dir_x, dir_y, dir_z, (1u << lanes) - 1u, hits, &counts);
  if (camera_hits)
    for (uint k = 0; k < lanes; ++k) camera_hits[first_sample + k] = hits[k];
  if (gbuffer)
    for (uint k = 0; k < lanes; ++k)
      store_gbuffer_texel(&scene, hit_of_bits(hits[k]), eye, forward, (uint2)(width, height), film_scale.y,
                          pixel_at_position(first_position + first_sample + k, width, height), gbuffer,
                          gbuffer_planes);
  const TraversalCounts sums = {sum_of_lanes(counts.nodes), sum_of_lanes(counts.leaves),
                                sum_of_lanes(counts.triangles), 0u};
  add_traversal_counts(traversal_totals, &sums);
}
#endif

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
static inline void origin_of_rays(const SceneView* scene, const Surface* from, uint rays,
                                  RayOrigin* origin) {
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
  cosine_directions_x4(from->shading_normal, philox_unit_floats(bits[0]), philox_unit_floats(bits[1]), &x, &y,
                       &z);
  dir[0] = (float3)(x.s0, y.s0, z.s0);
  dir[1] = (float3)(x.s1, y.s1, z.s1);
  dir[2] = (float3)(x.s2, y.s2, z.s2);
  dir[3] = (float3)(x.s3, y.s3, z.s3);
  for (uint j = 0; j < 4; ++j) cast[j] = mirrored_above(from->geometric_normal, &dir[j]);
}

// Draws the direction of one AO ray from `from` and traces it from `origin`,
// where its rays start. A hit point is only needed where the estimator bounces
// on; elsewhere any hit will do.
static inline int cast_ao_ray(const SceneView* scene, const Surface* from, const RayOrigin* origin,
                              const AoSettings* s, uint pixel, uint camera_sample, uint bounce,
                              uint node, int need_hit_point, float3* dir, Hit* hit, uint* rays,
                              TraversalCounts* counts) {
  if (!ao_ray_direction(from, s, pixel, camera_sample, bounce, node, dir)) return MBAO_RAY_BLOCKED;
  ++*rays;
  return trace_ray_from(scene, origin, *dir, s->max_distance, !need_hit_point, hit, counts)
             ? MBAO_RAY_HIT
             : MBAO_RAY_ESCAPED;
}

static inline int bounces_on(const AoSettings* s, uint bounce) {
  return bounce < s->bounces && s->rho > 0.0f;
}

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
static float branching_estimate(const SceneView* scene, const Surface* primary,
                                const AoSettings* s, uint pixel, uint camera_sample, uint* rays,
                                TraversalCounts* counts, DirectionMoments* moments) {
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
    const int outcome = cast_ao_ray(scene, &surface[level], &origin[level], s, pixel, camera_sample,
                                    bounce, child, bounce_on, &dir, &hit, rays, counts);
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
static float path_estimate(const SceneView* scene, const Surface* primary, const AoSettings* s,
                           uint pixel, uint camera_sample, uint* rays, TraversalCounts* counts,
                           DirectionMoments* moments) {
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
      const int outcome = cast_ao_ray(scene, &surface, from, s, pixel, camera_sample, bounce, path,
                                      bounce_on, &dir, &hit, rays, counts);
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
static inline float pixel_variance(float sum, float sum_of_squares, uint spp, DirectionMoments directions,
                                   uint r) {
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
static inline void store_pixel(uint pixel, float sum, float sum_of_squares, DirectionMoments directions,
                               uint spp, uint r, uint covered, uint rays, __global float* ao,
                               __global float* ao_second_moment, __global float* ao_variance,
                               __global uchar* coverage, __global uint* secondary_rays) {
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
static inline void shade_pixel(const SceneView* scene, int estimator, float4 eye, uint spp,
                               const AoSettings* s, uint first_position, uint pixel_index,
                               __global const uint4* camera_hits, __global float* ao,
                               __global float* ao_second_moment, __global float* ao_variance,
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
  store_pixel(pixel, sum, sum_of_squares, directions, spp, s->samples, covered, rays, ao, ao_second_moment,
              ao_variance, coverage, secondary_rays);
  add_traversal_counts(traversal_totals, &counts);
}

// The megakernel: one work item per pixel runs the whole estimator.
#define MBAO_AO_KERNEL(name, estimator)                                                            \
  __kernel void name(MBAO_SCENE_PARAMS, MBAO_AO_PARAMS uint first_position, uint pixel_count,      \
                     __global const uint4 *camera_hits, __global float *ao,                        \
                     __global float *ao_second_moment, __global float *ao_variance,                \
                     __global uchar *coverage, __global uint *secondary_rays,                      \
                     __global ulong *traversal_totals) {                                           \
    const uint pixel_index = get_global_id(0);                                                     \
    if (pixel_index >= pixel_count) return;                                                        \
    const SceneView scene = MBAO_SCENE_VIEW();                                                     \
    const AoSettings s = MBAO_AO_SETTINGS();                                                       \
    shade_pixel(&scene, estimator, eye, spp, &s, first_position, pixel_index, camera_hits, ao,     \
                ao_second_moment, ao_variance, coverage, secondary_rays, traversal_totals);        \
  }

MBAO_AO_KERNEL(ao_branching, MBAO_ESTIMATOR_BRANCHING)
MBAO_AO_KERNEL(ao_path, MBAO_ESTIMATOR_PATH)

// The wavefront organisation of the branching estimator: one launch per bounce
// over a queue of the surfaces that bounce on, so that escaped and blocked rays
// stop costing work items and neighbouring work items trace rays of the same
// bounce. It keeps the megakernel's random numbers (keyed by pixel, camera
// sample, bounce and node, not by order) and its escape counts per bounce, so
// its image is the megakernel's bit for bit. Per camera sample of the tile the
// kernels keep escape_counts[sample * bounces + bounce - 1] and sample_rays[sample];
// queue k holds the surfaces that bounce k hit and that bounce k + 1 leaves
// from, queue_lengths[k] entries of it.

static inline QueuedSurface queued_surface(Hit hit, float3 incoming, uint sample, uint node) {
  QueuedSurface q;
  q.triangle = hit.triangle;
  q.b1 = hit.b1;
  q.b2 = hit.b2;
  q.incoming_x = incoming.x;
  q.incoming_y = incoming.y;
  q.incoming_z = incoming.z;
  q.sample = sample;
  q.node = node;
  return q;
}

static inline Surface dequeued_surface(const SceneView* scene, QueuedSurface q) {
  Hit hit;
  hit.t = 0.0f;  // make_surface interpolates the corners; t is not needed
  hit.triangle = q.triangle;
  hit.b1 = q.b1;
  hit.b2 = q.b2;
  return make_surface(scene, hit, (float3)(q.incoming_x, q.incoming_y, q.incoming_z));
}

// What one AO ray of bounce `bounce` adds: an escape, or, where the estimator
// bounces on, the surface it hit for the next bounce to leave from, appended
// to queue `bounce` (in no particular order: nothing depends on it).
static inline void tally_ray(int outcome, int bounce_on, Hit hit, float3 dir, uint sample, uint node, uint bounce,
                             __global QueuedSurface* next, __global uint* queue_lengths, uint* escapes) {
  if (outcome == MBAO_RAY_ESCAPED)
    ++*escapes;
  else if (outcome == MBAO_RAY_HIT && bounce_on)
    next[atomic_inc(&queue_lengths[bounce])] = queued_surface(hit, dir, sample, node);
}

// Where the escapes at bounce `bounce` of a camera sample are counted: one
// count per camera sample, or, keeping direction moments, one per direction
// drawn at its primary hit, which the ray descends from.
static inline uint escape_slot(uint sample, uint direction, uint bounce, const AoSettings* s) {
  return s->direction_moments ? (sample * s->samples + direction) * s->bounces + bounce - 1
                              : sample * s->bounces + bounce - 1;
}

// The direction drawn at the primary hit that `node` of bounce `bounce` descends from.
static inline uint first_direction(uint node, uint bounce, uint r) {
  for (uint k = 1; k < bounce; ++k) node /= r;
  return node;
}

// Starts the counts of one direction drawn at a primary hit (direction
// moments only; without them count_source starts the camera sample's).
static inline void start_direction_counts(uint sample, uint direction, int outcome, const AoSettings* s,
                                          __global uint* escape_counts) {
  if (!s->direction_moments) return;
  escape_counts[escape_slot(sample, direction, 1, s)] = outcome == MBAO_RAY_ESCAPED;
  for (uint k = 2; k <= s->bounces; ++k) escape_counts[escape_slot(sample, direction, k, s)] = 0;
}

// A source's escapes and rays into its camera sample's counts. Bounce 1 has
// one source per camera sample and starts them, so they need no clearing and
// there no atomics; later bounces add to them.
static inline void count_source(uint bounce, uint sample, uint node, uint escapes, uint rays, const AoSettings* s,
                                __global uint* escape_counts, __global uint* sample_rays) {
  if (bounce == 1) {
    if (!s->direction_moments) {
      escape_counts[escape_slot(sample, 0, 1, s)] = escapes;
      for (uint k = 2; k <= s->bounces; ++k) escape_counts[escape_slot(sample, 0, k, s)] = 0;
    }
    sample_rays[sample] = rays;
    return;
  }
  const uint slot = escape_slot(sample, first_direction(node, bounce - 1, s->samples), bounce, s);
  if (escapes) atomic_add(&escape_counts[slot], escapes);
  if (rays) atomic_add(&sample_rays[sample], rays);
}

// The r rays from one surface of a tile's camera sample `sample`.
static void cast_children(const SceneView* scene, const Surface* from, const AoSettings* s,
                          uint spp, uint first_position, uint sample, uint bounce, uint node,
                          __global QueuedSurface* next, __global uint* queue_lengths,
                          __global uint* escape_counts, uint* escapes, uint* rays, TraversalCounts* counts) {
  const uint pixel = tile_pixel(s, first_position, sample / spp);
  const uint camera_sample = sample % spp;
  const int bounce_on = bounces_on(s, bounce);
  RayOrigin origin;
  origin_of_rays(scene, from, s->samples, &origin);
  for (uint i = 0; i < s->samples; ++i) {
    const uint child = node * s->samples + i;
    float3 dir;
    Hit hit;
    const int outcome = cast_ao_ray(scene, from, &origin, s, pixel, camera_sample, bounce, child,
                                    bounce_on, &dir, &hit, rays, counts);
    tally_ray(outcome, bounce_on, hit, dir, sample, child, bounce, next, queue_lengths, escapes);
    if (bounce == 1) start_direction_counts(sample, i, outcome, s, escape_counts);
  }
}

// Bounce 1, one work item per camera sample of the tile.
__kernel void wavefront_first_bounce(MBAO_SCENE_PARAMS, MBAO_AO_PARAMS uint first_position,
                                     uint sample_count, __global const uint4* camera_hits,
                                     __global uint* escape_counts, __global uint* sample_rays,
                                     __global QueuedSurface* next, __global uint* queue_lengths,
                                     __global ulong* traversal_totals) {
  const uint sample = get_global_id(0);
  if (sample >= sample_count) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  const AoSettings s = MBAO_AO_SETTINGS();
  uint escapes = 0, rays = 0;
  TraversalCounts counts = no_traversal_counts();
  const Hit hit = stored_hit(camera_hits, sample);
  if (hit.triangle != MBAO_NO_TRIANGLE) {
    const Surface primary = primary_surface(&scene, hit, eye);
    cast_children(&scene, &primary, &s, spp, first_position, sample, 1, 0, next, queue_lengths, escape_counts,
                  &escapes, &rays, &counts);
  }
  count_source(1, sample, 0, escapes, rays, &s, escape_counts, sample_rays);
  add_traversal_counts(traversal_totals, &counts);
}

// Bounce 2 and on, one work item per surface in queue bounce - 1 (the launch
// has at least that many).
__kernel void wavefront_bounce(MBAO_SCENE_PARAMS, MBAO_AO_PARAMS uint first_position, uint bounce,
                               __global const QueuedSurface* queue, __global uint* escape_counts,
                               __global uint* sample_rays, __global QueuedSurface* next,
                               __global uint* queue_lengths, __global ulong* traversal_totals) {
  const uint index = get_global_id(0);
  if (index >= queue_lengths[bounce - 1]) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  const AoSettings s = MBAO_AO_SETTINGS();
  const QueuedSurface entry = queue[index];
  const Surface from = dequeued_surface(&scene, entry);
  uint escapes = 0, rays = 0;
  TraversalCounts counts = no_traversal_counts();
  cast_children(&scene, &from, &s, spp, first_position, entry.sample, bounce, entry.node, next,
                queue_lengths, escape_counts, &escapes, &rays, &counts);
  count_source(bounce, entry.sample, entry.node, escapes, rays, &s, escape_counts, sample_rays);
  add_traversal_counts(traversal_totals, &counts);
}

// A camera sample's value from its escape counts, as the megakernel's; with
// direction moments, its directions' values added to `directions`.
static inline float branching_value_of_counts(__global const uint* escape_counts, uint sample, const AoSettings* s,
                                              DirectionMoments* directions) {
  uint escapes[MBAO_MAX_BRANCHING_BOUNCES];
  for (uint k = 0; k < s->bounces; ++k) escapes[k] = 0;
  if (!s->direction_moments) {
    for (uint k = 0; k < s->bounces; ++k) escapes[k] = escape_counts[escape_slot(sample, 0, k + 1, s)];
    return branching_value(escapes, s);
  }
  for (uint direction = 0; direction < s->samples; ++direction) {
    uint subtree[MBAO_MAX_BRANCHING_BOUNCES];
    for (uint k = 0; k < s->bounces; ++k) {
      subtree[k] = escape_counts[escape_slot(sample, direction, k + 1, s)];
      escapes[k] += subtree[k];
    }
    add_direction_value(direction_value(subtree, s), directions);
  }
  return branching_value(escapes, s);
}

// One work item per pixel of the tile: its camera samples' values, summed in
// the megakernel's order.
__kernel void wavefront_finish(MBAO_AO_PARAMS uint first_position, uint pixel_count,
                               __global const uint4* camera_hits,
                               __global const uint* escape_counts,
                               __global const uint* sample_rays, __global float* ao,
                               __global float* ao_second_moment, __global float* ao_variance,
                               __global uchar* coverage, __global uint* secondary_rays) {
  const uint pixel_index = get_global_id(0);
  if (pixel_index >= pixel_count) return;
  const AoSettings s = MBAO_AO_SETTINGS();
  float sum = 0.0f, sum_of_squares = 0.0f;
  DirectionMoments directions = {0.0f, 0.0f};
  uint covered = 0, rays = 0;
  for (uint camera_sample = 0; camera_sample < spp; ++camera_sample) {
    const uint sample = pixel_index * spp + camera_sample;
    rays += sample_rays[sample];
    float value = 1.0f;
    if (camera_hits[sample].y != MBAO_NO_TRIANGLE) {
      ++covered;
      value = branching_value_of_counts(escape_counts, sample, &s, &directions);
    }
    sum += value;
    sum_of_squares += value * value;
  }
  store_pixel(tile_pixel(&s, first_position, pixel_index), sum, sum_of_squares, directions, spp, samples, covered,
              rays, ao, ao_second_moment, ao_variance, coverage, secondary_rays);
}

// The wavefront with traversal "lanes": a bounce in three launches over a
// stream of rays, so that the walk takes them sixteen at a time (kd_lanes.h).
// The bounce's sources are the surfaces it leaves from, the tile's camera
// samples for bounce 1 and queue bounce - 1 after; a launch takes the sources
// [first_source, first_source + source_count), and source j's r rays fill
// stream slots (j - first_source) * r + i. The sources' rays, random numbers,
// escape counts and queue entries are the wavefront's above, so is the image.

// Source `index` of bounce `bounce`: its camera sample within the tile and its
// node in the estimator's tree.
static inline void stream_source(uint bounce, uint index, __global const QueuedSurface* queue, uint* sample,
                                 uint* node) {
  if (bounce == 1) {
    *sample = index;
    *node = 0;
  } else {
    *sample = queue[index].sample;
    *node = queue[index].node;
  }
}

// The r rays of each source; a blocked ray, or any ray of a camera sample
// that hit nothing, gets t_max -1 (no ray).
__kernel void stream_bounce_rays(MBAO_SCENE_PARAMS, MBAO_AO_PARAMS uint first_position, uint bounce,
                                 uint first_source, uint source_count, __global const uint4* camera_hits,
                                 __global const QueuedSurface* queue, __global float4* ray_origins,
                                 __global float4* ray_directions) {
  const uint slot = get_global_id(0);
  if (slot >= source_count) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  const AoSettings s = MBAO_AO_SETTINGS();
  const uint index = first_source + slot;
  uint sample, node;
  stream_source(bounce, index, queue, &sample, &node);
  __global float4* origins = ray_origins + slot * s.samples;
  __global float4* directions = ray_directions + slot * s.samples;
  Surface from;
  if (bounce == 1) {
    const Hit hit = stored_hit(camera_hits, index);
    if (hit.triangle == MBAO_NO_TRIANGLE) {
      for (uint i = 0; i < s.samples; ++i) directions[i] = (float4)(0.0f, 0.0f, 1.0f, -1.0f);
      return;
    }
    from = primary_surface(&scene, hit, eye);
  } else {
    from = dequeued_surface(&scene, queue[index]);
  }
  const float4 point = (float4)(leaving_point(&from), 0.0f);
  const uint pixel = tile_pixel(&s, first_position, sample / spp);
  uint i = 0;
  // Four at a time on vectors: drawing them one by one, this kernel took about
  // twice the time on PoCL (docs/traversal.md).
  for (; i + 4 <= s.samples; i += 4) {
    float3 dir[4];
    int cast[4];
    ao_ray_directions_x4(&from, &s, pixel, sample % spp, bounce, node * s.samples + i, dir, cast);
    for (uint j = 0; j < 4; ++j) {
      origins[i + j] = point;
      directions[i + j] = (float4)(dir[j], cast[j] ? s.max_distance : -1.0f);
    }
  }
  for (; i < s.samples; ++i) {
    float3 dir;
    const int cast = ao_ray_direction(&from, &s, pixel, sample % spp, bounce, node * s.samples + i, &dir);
    origins[i] = point;
    directions[i] = (float4)(dir, cast ? s.max_distance : -1.0f);
  }
}

// Each source's rays' outcomes (tally_ray), counted to its camera sample (count_source).
__kernel void stream_bounce_hits(MBAO_AO_PARAMS uint bounce, uint first_source, uint source_count,
                                 __global const QueuedSurface* queue, __global const float4* ray_directions,
                                 __global const uint4* ray_hits, __global uint* escape_counts,
                                 __global uint* sample_rays, __global QueuedSurface* next,
                                 __global uint* queue_lengths) {
  const uint slot = get_global_id(0);
  if (slot >= source_count) return;
  const AoSettings s = MBAO_AO_SETTINGS();
  uint sample, node;
  stream_source(bounce, first_source + slot, queue, &sample, &node);
  const int bounce_on = bounces_on(&s, bounce);
  uint escapes = 0, rays = 0;
  for (uint i = 0; i < s.samples; ++i) {
    const uint ray = slot * s.samples + i;
    const float4 direction = ray_directions[ray];
    int outcome = MBAO_RAY_BLOCKED;
    if (direction.w >= 0.0f) {
      ++rays;
      const Hit hit = stored_hit(ray_hits, ray);
      outcome = hit.triangle == MBAO_NO_TRIANGLE ? MBAO_RAY_ESCAPED : MBAO_RAY_HIT;
      tally_ray(outcome, bounce_on, hit, direction.xyz, sample, node * s.samples + i, bounce, next,
                queue_lengths, &escapes);
    }
    if (bounce == 1) start_direction_counts(sample, i, outcome, &s, escape_counts);
  }
  count_source(bounce, sample, node, escapes, rays, &s, escape_counts, sample_rays);
}
