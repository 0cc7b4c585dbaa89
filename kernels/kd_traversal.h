// Stackless kd-tree traversal: kd-restart (Foley and Sugerman 2005) and kd
// push-down (Horn et al. 2007), chosen at compile time with MBAO_TRAVERSAL.
//
// Both walk the leaves along the ray front to back, one leaf per descent. A
// descent narrows the interval [t_lo, t_hi] to one leaf; when the leaf holds
// no hit, the next descent starts at t_lo = t_hi. Restart begins each descent
// at the root; push-down begins at the deepest node whose cell held the whole
// remaining interval, found on the way down.
//
// The tree puts every triangle into every leaf whose closed cell it touches.
// A point on a cell boundary is therefore tested in each leaf that touches it,
// which is what lets a descent skip an interval of zero length and always move
// forward, and makes closest hits independent of the leaf order.
#ifndef MBAO_KD_TRAVERSAL_H
#define MBAO_KD_TRAVERSAL_H

#include "scene.h"

#define MBAO_TRAVERSAL_RESTART 0
#define MBAO_TRAVERSAL_PUSHDOWN 1
#ifndef MBAO_TRAVERSAL
#define MBAO_TRAVERSAL MBAO_TRAVERSAL_PUSHDOWN
#endif

// Finds the closest hit with 0 < t <= t_max (ties go to the lower triangle id),
// or with any_hit, any hit in that range. Returns 1 on a hit; *hit is no_hit()
// on a miss.
static inline int trace_ray(const SceneView* scene, float3 origin, float3 dir, float t_max,
                            int any_hit, Hit* hit) {
  *hit = no_hit();
  const float3 inv_dir = 1.0f / dir;
  float t_enter, t_exit;
  if (!clip_to_box(origin, dir, inv_dir, scene->bounds_lo, scene->bounds_hi, t_max, &t_enter,
                   &t_exit))
    return 0;
  const WatertightRay ray = make_watertight_ray(origin, dir);

  Hit best = no_hit();
  best.t = t_max;
  uint start_node = 0;
  float t_lo = t_enter;
  do {
    uint index = start_node;
    float t_hi = t_exit;
    int whole_interval_inside = 1;
    KdNode node = scene->nodes[index];
    while (!kd_is_leaf(node)) {
      const int axis = (int)kd_axis(node);
      const float split = kd_split(node);
      const float o = component(origin, axis);
      const float d = component(dir, axis);
      const float t_split = (split - o) * component(inv_dir, axis);
      const int below_first = (o < split) || (o == split && d <= 0.0f);
      const uint below = index + 1;
      const uint above = kd_above_child(node);
      const uint first = below_first ? below : above;
      const uint second = below_first ? above : below;
      // NaN t_split (a ray lying in the plane) goes to the first child only.
      if (!(t_split > 0.0f) || t_split > t_hi) {
        index = first;
      } else if (t_split <= t_lo) {
        index = second;
      } else {
        index = first;
        t_hi = t_split;
        whole_interval_inside = 0;
      }
#if MBAO_TRAVERSAL == MBAO_TRAVERSAL_PUSHDOWN
      if (whole_interval_inside) start_node = index;
#endif
      node = scene->nodes[index];
    }

    const uint first_entry = kd_first_index(node);
    const uint end_entry = first_entry + kd_triangle_count(node);
    for (uint entry = first_entry; entry < end_entry; ++entry) {
      const uint triangle = scene->leaf_triangles[entry];
      float t, b1, b2;
      if (!intersect_triangle(&ray, triangle_corner(scene, triangle, 0),
                              triangle_corner(scene, triangle, 1),
                              triangle_corner(scene, triangle, 2), best.t, &t, &b1, &b2) ||
          !hit_is_solid(scene, triangle, b1, b2))
        continue;
      if (t < best.t || triangle < best.triangle) {
        best.t = t;
        best.triangle = triangle;
        best.b1 = b1;
        best.b2 = b2;
        if (any_hit) {
          *hit = best;
          return 1;
        }
      }
    }
    if (best.triangle != MBAO_NO_TRIANGLE && best.t <= t_hi) break;
    t_lo = t_hi;
  } while (t_lo < t_exit);

  if (best.triangle == MBAO_NO_TRIANGLE) return 0;
  *hit = best;
  return 1;
}

#endif
