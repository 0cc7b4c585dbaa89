// kd-tree traversal, in the four ways of MBAO_TRAVERSAL:
//   restart     (Foley and Sugerman 2005): no stack; every leaf after the first
//               is found by a new descent from the root;
//   push-down   (Horn et al. 2007): no stack; a new descent starts at the
//               deepest node whose cell held the whole remaining interval;
//   short stack (Horn et al. 2007): push-down plus a small circular stack of
//               far children; a descent restarts only when the stack runs dry;
//   stack       a stack as deep as the tree: every node is visited once.
// All walk the leaves along the ray front to back and return the same hit.
//
// A descent narrows the interval [t_lo, t_hi] to one leaf; when the leaf holds
// no hit, the walk goes on at t_lo = t_hi. The tree puts every triangle into
// every leaf whose closed cell it touches, so a point on a cell boundary is
// tested in each leaf that touches it: after the first leaf a descent can skip
// a child whose interval has zero length, and every descent moves forward.
#ifndef MBAO_KD_TRAVERSAL_H
#define MBAO_KD_TRAVERSAL_H

#include "mbao/limits.h"
#include "scene.h"

#define MBAO_TRAVERSAL_RESTART 0
#define MBAO_TRAVERSAL_PUSHDOWN 1
#define MBAO_TRAVERSAL_SHORT_STACK 2
#define MBAO_TRAVERSAL_STACK 3
#ifndef MBAO_TRAVERSAL
#define MBAO_TRAVERSAL MBAO_TRAVERSAL_PUSHDOWN
#endif

// Stack entries (a power of two: the short stack wraps around) and whether
// descents remember a push-down node.
#if MBAO_TRAVERSAL == MBAO_TRAVERSAL_RESTART
#define MBAO_STACK_SIZE 0
#define MBAO_PUSH_DOWN 0
#elif MBAO_TRAVERSAL == MBAO_TRAVERSAL_PUSHDOWN
#define MBAO_STACK_SIZE 0
#define MBAO_PUSH_DOWN 1
#elif MBAO_TRAVERSAL == MBAO_TRAVERSAL_SHORT_STACK
#ifndef MBAO_SHORT_STACK_SIZE
#define MBAO_SHORT_STACK_SIZE 4
#endif
#define MBAO_STACK_SIZE MBAO_SHORT_STACK_SIZE
#define MBAO_PUSH_DOWN 1
#else
#define MBAO_STACK_SIZE MBAO_KD_MAX_DEPTH
#define MBAO_PUSH_DOWN 0
#endif

// What a walk cost, counted only in programs built with MBAO_COUNT_TRAVERSAL.
typedef struct TraversalCounts {
  uint nodes;      // nodes fetched, interior and leaf
  uint leaves;
  uint triangles;  // ray/triangle tests
  uint restarts;   // descents from the root or push-down node after the first
} TraversalCounts;

#ifndef MBAO_COUNT_TRAVERSAL
#define MBAO_COUNT_TRAVERSAL 0
#endif
#if MBAO_COUNT_TRAVERSAL
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#define MBAO_COUNT(counts, field, n) ((counts)->field += (n))
// Adds a work item's counts to the frame's four totals.
static inline void add_traversal_counts(__global ulong* totals, const TraversalCounts* counts) {
  atom_add(&totals[0], (ulong)counts->nodes);
  atom_add(&totals[1], (ulong)counts->leaves);
  atom_add(&totals[2], (ulong)counts->triangles);
  atom_add(&totals[3], (ulong)counts->restarts);
}
#else
#define MBAO_COUNT(counts, field, n) ((void)0)
#endif

static inline TraversalCounts no_traversal_counts(void) {
  TraversalCounts counts = {0, 0, 0, 0};
  return counts;
}

// Tests the triangles of a leaf against the ray, keeping the closest hit in
// *best (ties to the lower triangle id). Returns 1 when any_hit and a hit was found.
static inline int test_leaf(const SceneView* scene, const WatertightRay* ray, KdNode leaf, int any_hit,
                            Hit* best, TraversalCounts* counts) {
  const uint first_entry = kd_first_index(leaf);
  const uint end_entry = first_entry + kd_triangle_count(leaf);
  MBAO_COUNT(counts, triangles, end_entry - first_entry);
  for (uint entry = first_entry; entry < end_entry; ++entry) {
    const uint triangle = scene->leaf_triangles[entry];
    float t, b1, b2;
    __global const float4* corners = scene->triangle_corners + 3 * triangle;
    if (!intersect_triangle(ray, corners[0], corners[1], corners[2], best->t, &t, &b1, &b2) ||
        !hit_is_solid(scene, triangle, b1, b2))
      continue;
    if (t < best->t || triangle < best->triangle) {
      best->t = t;
      best->triangle = triangle;
      best->b1 = b1;
      best->b2 = b2;
      if (any_hit) return 1;
    }
  }
  return 0;
}

// Finds the closest hit with 0 < t <= t_max (ties go to the lower triangle id),
// or with any_hit, any hit in that range. Returns 1 on a hit; *hit is no_hit()
// on a miss.
static inline int trace_ray(const SceneView* scene, float3 origin, float3 dir, float t_max,
                            int any_hit, Hit* hit, TraversalCounts* counts) {
  *hit = no_hit();
  const float3 inv_dir = 1.0f / dir;
  float t_enter, t_exit;
  if (!clip_to_box(origin, dir, inv_dir, scene->bounds_lo, scene->bounds_hi, t_max, &t_enter,
                   &t_exit))
    return 0;
  const WatertightRay ray = make_watertight_ray(origin, dir, scene->bounds_lo, scene->bounds_hi);
  // Per axis, for the descent: indexing an array costs one load, picking a
  // vector component by a run-time axis a chain of selects.
  const float origin_of[3] = {origin.x, origin.y, origin.z};
  const float dir_of[3] = {dir.x, dir.y, dir.z};
  const float inv_dir_of[3] = {inv_dir.x, inv_dir.y, inv_dir.z};

  Hit best = no_hit();
  best.t = t_max;
  uint start_node = 0;
  float t_lo = t_enter;
  int resumed = 0;  // past the first leaf: zero-length intervals may be skipped
#if MBAO_STACK_SIZE > 0
  uint stack_node[MBAO_STACK_SIZE];
  float stack_lo[MBAO_STACK_SIZE], stack_hi[MBAO_STACK_SIZE];
  uint stack_top = 0, stack_count = 0;  // next free slot; entries held (the oldest are overwritten)
#endif
  for (;;) {
    uint index;
    float t_hi;
    int whole_interval_inside;  // so far, the walk's whole remaining interval lies in `index`'s cell
#if MBAO_STACK_SIZE > 0
    if (stack_count > 0) {
      stack_top = (stack_top - 1) & (MBAO_STACK_SIZE - 1);
      --stack_count;
      index = stack_node[stack_top];
      t_lo = stack_lo[stack_top];
      t_hi = stack_hi[stack_top];
      whole_interval_inside = 0;
    } else
#endif
    {
      index = start_node;
      t_hi = t_exit;
      whole_interval_inside = 1;
      if (resumed) MBAO_COUNT(counts, restarts, 1);
    }

    KdNode node = scene->nodes[index];
    MBAO_COUNT(counts, nodes, 1);
    while (!kd_is_leaf(node)) {
      const uint axis = kd_axis(node);
      const float split = kd_split(node);
      const float o = origin_of[axis];
      const float d = dir_of[axis];
      const float t_split = (split - o) * inv_dir_of[axis];
      const int below_first = (o < split) || (o == split && d <= 0.0f);
      const uint below = index + 1;
      const uint above = kd_above_child(node);
      const uint first = below_first ? below : above;
      const uint second = below_first ? above : below;
      // NaN t_split (a ray lying in the plane) goes to the first child only.
      if (!(t_split > 0.0f) || t_split > t_hi) {
        index = first;
      } else if (t_split < t_lo || (resumed && t_split == t_lo)) {
        index = second;
      } else {
#if MBAO_STACK_SIZE > 0
        stack_node[stack_top] = second;
        stack_lo[stack_top] = t_split;
        stack_hi[stack_top] = t_hi;
        stack_top = (stack_top + 1) & (MBAO_STACK_SIZE - 1);
        stack_count = min(stack_count + 1, (uint)MBAO_STACK_SIZE);
#endif
        index = first;
        t_hi = t_split;
        whole_interval_inside = 0;
      }
#if MBAO_PUSH_DOWN
      if (whole_interval_inside) start_node = index;
#endif
      node = scene->nodes[index];
      MBAO_COUNT(counts, nodes, 1);
    }

    MBAO_COUNT(counts, leaves, 1);
    if (test_leaf(scene, &ray, node, any_hit, &best, counts)) break;
    if (best.triangle != MBAO_NO_TRIANGLE && best.t <= t_hi) break;
    t_lo = t_hi;
    resumed = 1;
#if MBAO_STACK_SIZE > 0
    if (stack_count == 0 && t_lo >= t_exit) break;
#else
    if (t_lo >= t_exit) break;
#endif
  }

  if (best.triangle == MBAO_NO_TRIANGLE) return 0;
  *hit = best;
  return 1;
}

#endif
