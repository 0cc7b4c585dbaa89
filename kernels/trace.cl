// Rays given by the caller, traced as they are: the ray-query API and the
// kernel the traversal tests compare against brute force. With traversal
// "lanes" the API launches kd_lanes.h's trace_rays_in_lanes instead.
#include "kd_lanes.h"

// directions[i].w is the ray's t_max. Each hit is stored as (t, triangle, b1, b2)
// bits; programs built with MBAO_COUNT_TRAVERSAL also store each ray's counts.
__kernel void trace_rays(MBAO_SCENE_PARAMS, __global const float4* origins, __global const float4* directions,
                         uint count, int any_hit, __global uint4* hits, __global uint4* ray_counts) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  Hit hit;
  TraversalCounts counts = no_traversal_counts();
  trace_ray(&scene, origins[i].xyz, directions[i].xyz, directions[i].w, any_hit, &hit, &counts);
  hits[i] = bits_of_hit(hit);
  if (MBAO_COUNT_TRAVERSAL) ray_counts[i] = (uint4)(counts.nodes, counts.leaves, counts.triangles, counts.restarts);
}
