// The camera rays of a frame (SPEC 1): each pixel's hits, and the G-buffer
// planes of those through the pixel centres.
#ifndef MBAO_RENDER_CAMERA_RAYS_H
#define MBAO_RENDER_CAMERA_RAYS_H

#include "mbao/param_groups.h"
#include "mbao/gbuffer.h"
#include "mbao/pixel_order.h"
#include "kd_packet.h"
#include "surface.h"
#include "sampling.h"
#include "camera.h"

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
static inline void store_gbuffer_texel(const SceneView* scene, Hit hit, float4 eye, float4 forward, uint2 image_size,
                                       float film_scale_y, uint pixel, __global float* gbuffer, uint planes) {
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
#define MBAO_CAMERA_RAY_PARAMS                                                                       \
  MBAO_SCENE_PARAMS, MBAO_CAMERA_PARAMS uint spp, uint2 seed, uint first_position, uint pixel_count, \
      __global uint4 *camera_hits, __global ulong *traversal_totals, __global float *gbuffer, uint gbuffer_planes

__kernel void trace_camera_rays(MBAO_CAMERA_RAY_PARAMS) {
  const uint sample_index = get_global_id(0);
  if (sample_index >= pixel_count * spp) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  const float3 dir =
      camera_sample_direction(forward, right, up, film_scale, width, height, spp, seed, first_position, sample_index);
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
    const float3 dir = camera_sample_direction(forward, right, up, film_scale, width, height, spp, seed, first_position,
                                               first_sample + k);
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
                          pixel_at_position(first_position + first_sample + k, width, height), gbuffer, gbuffer_planes);
  const TraversalCounts sums = {sum_of_lanes(counts.nodes), sum_of_lanes(counts.leaves), sum_of_lanes(counts.triangles),
                                0u};
  add_traversal_counts(traversal_totals, &sums);
}
#endif

#endif
