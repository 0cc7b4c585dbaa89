// The wavefront with traversal "lanes": a bounce in three launches over a
// stream of rays, so that the walk takes them sixteen at a time (kd_lanes.h).
// The bounce's sources are the surfaces it leaves from, the tile's camera
// samples for bounce 1 and queue bounce - 1 after; a launch takes the sources
// [first_source, first_source + source_count), and source j's r rays fill
// stream slots (j - first_source) * r + i. The sources' rays, random numbers,
// escape counts and queue entries are the wavefront's (wavefront_bounces.h), so is the image.
#ifndef MBAO_RENDER_STREAMED_BOUNCES_H
#define MBAO_RENDER_STREAMED_BOUNCES_H

#include "render/wavefront_bounces.h"

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
__kernel void stream_bounce_rays(MBAO_SCENE_PARAMS, MBAO_AO_PARAMS uint first_position, uint bounce, uint first_source,
                                 uint source_count, __global const uint4* camera_hits,
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
      tally_ray(outcome, bounce_on, hit, direction.xyz, sample, node * s.samples + i, bounce, next, queue_lengths,
                &escapes);
    }
    if (bounce == 1) start_direction_counts(sample, i, outcome, &s, escape_counts);
  }
  count_source(bounce, sample, node, escapes, rays, &s, escape_counts, sample_rays);
}

#endif
