// The wavefront organisation of the branching estimator: one launch per bounce
// over a queue of the surfaces that bounce on, so that escaped and blocked rays
// stop costing work items and neighbouring work items trace rays of the same
// bounce. It keeps the megakernel's random numbers (keyed by pixel, camera
// sample, bounce and node, not by order) and its escape counts per bounce, so
// its image is the megakernel's bit for bit. Per camera sample of the tile the
// kernels keep escape_counts[sample * bounces + bounce - 1] and sample_rays[sample];
// queue k holds the surfaces that bounce k hit and that bounce k + 1 leaves
// from, queue_lengths[k] entries of it.
#ifndef MBAO_RENDER_WAVEFRONT_BOUNCES_H
#define MBAO_RENDER_WAVEFRONT_BOUNCES_H

#include "mbao/wavefront.h"
#include "render/ao_estimators.h"

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
static void cast_children(const SceneView* scene, const Surface* from, const AoSettings* s, uint spp,
                          uint first_position, uint sample, uint bounce, uint node, __global QueuedSurface* next,
                          __global uint* queue_lengths, __global uint* escape_counts, uint* escapes, uint* rays,
                          TraversalCounts* counts) {
  const uint pixel = tile_pixel(s, first_position, sample / spp);
  const uint camera_sample = sample % spp;
  const int bounce_on = bounces_on(s, bounce);
  RayOrigin origin;
  origin_of_rays(scene, from, s->samples, &origin);
  for (uint i = 0; i < s->samples; ++i) {
    const uint child = node * s->samples + i;
    float3 dir;
    Hit hit;
    const int outcome =
        cast_ao_ray(scene, from, &origin, s, pixel, camera_sample, bounce, child, bounce_on, &dir, &hit, rays, counts);
    tally_ray(outcome, bounce_on, hit, dir, sample, child, bounce, next, queue_lengths, escapes);
    if (bounce == 1) start_direction_counts(sample, i, outcome, s, escape_counts);
  }
}

// Bounce 1, one work item per camera sample of the tile.
__kernel void wavefront_first_bounce(MBAO_SCENE_PARAMS, MBAO_AO_PARAMS uint first_position, uint sample_count,
                                     __global const uint4* camera_hits, __global uint* escape_counts,
                                     __global uint* sample_rays, __global QueuedSurface* next,
                                     __global uint* queue_lengths, __global ulong* traversal_totals) {
  const uint sample = get_global_id(0);
  if (sample >= sample_count) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  const AoSettings s = MBAO_AO_SETTINGS();
  uint escapes = 0, rays = 0;
  TraversalCounts counts = no_traversal_counts();
  const Hit hit = stored_hit(camera_hits, sample);
  if (hit.triangle != MBAO_NO_TRIANGLE) {
    const Surface primary = primary_surface(&scene, hit, eye);
    cast_children(&scene, &primary, &s, spp, first_position, sample, 1, 0, next, queue_lengths, escape_counts, &escapes,
                  &rays, &counts);
  }
  count_source(1, sample, 0, escapes, rays, &s, escape_counts, sample_rays);
  add_traversal_counts(traversal_totals, &counts);
}

// Bounce 2 and on, one work item per surface in queue bounce - 1 (the launch
// has at least that many).
__kernel void wavefront_bounce(MBAO_SCENE_PARAMS, MBAO_AO_PARAMS uint first_position, uint bounce,
                               __global const QueuedSurface* queue, __global uint* escape_counts,
                               __global uint* sample_rays, __global QueuedSurface* next, __global uint* queue_lengths,
                               __global ulong* traversal_totals) {
  const uint index = get_global_id(0);
  if (index >= queue_lengths[bounce - 1]) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  const AoSettings s = MBAO_AO_SETTINGS();
  const QueuedSurface entry = queue[index];
  const Surface from = dequeued_surface(&scene, entry);
  uint escapes = 0, rays = 0;
  TraversalCounts counts = no_traversal_counts();
  cast_children(&scene, &from, &s, spp, first_position, entry.sample, bounce, entry.node, next, queue_lengths,
                escape_counts, &escapes, &rays, &counts);
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
__kernel void wavefront_finish(MBAO_AO_PARAMS uint first_position, uint pixel_count, __global const uint4* camera_hits,
                               __global const uint* escape_counts, __global const uint* sample_rays, __global float* ao,
                               __global float* ao_second_moment, __global float* ao_variance, __global uchar* coverage,
                               __global uint* secondary_rays) {
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
  store_pixel(tile_pixel(&s, first_position, pixel_index), sum, sum_of_squares, directions, spp, samples, covered, rays,
              ao, ao_second_moment, ao_variance, coverage, secondary_rays);
}

#endif
