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
#ifndef MBAO_LOAD_BOTH_CHILDREN
#define MBAO_LOAD_BOTH_CHILDREN 0
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
    if (!intersect_triangle(ray, scene->triangles + triangle, best->t, &t, &b1, &b2) ||
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

#if MBAO_STACK_SIZE > 0
// The far children a descent passed by, each with the end of its interval. Its
// start need not be kept: the intervals of the leaves a walk visits follow one
// another, so a popped child's interval starts where the leaf before it ended,
// which is where the walk stands. The entries, (node, t_hi bits), lie in an
// array the walk declares, one slot more than the stack holds, written by the
// steps that push nothing (a descent step does not branch on whether it
// pushes). The array is not a member: beside an array indexed at run time the
// compiler left the counters in memory, and every step waited on a store and
// a load of `top` (docs/traversal-on-pocl.md).
typedef struct FarStack {
  __private uint2* entries;
  uint top;    // next free slot
  uint count;  // entries held by the short stack, which overwrites its oldest (the full stack's is top)
} FarStack;

static inline void far_stack_push_if(FarStack* stack, uint push, uint node, float t_hi) {
#if MBAO_TRAVERSAL == MBAO_TRAVERSAL_STACK
  // It holds at most one entry per tree level, so top never passes the spare slot.
  const uint slot = stack->top;
  stack->top += push;
#else
  const uint slot = push ? stack->top : MBAO_STACK_SIZE;
  stack->top = (stack->top + push) & (MBAO_STACK_SIZE - 1);
  stack->count = min(stack->count + push, (uint)MBAO_STACK_SIZE);
#endif
  stack->entries[slot] = (uint2)(node, as_uint(t_hi));
}

static inline int far_stack_is_empty(const FarStack* stack) {
#if MBAO_TRAVERSAL == MBAO_TRAVERSAL_STACK
  return stack->top == 0;
#else
  return stack->count == 0;
#endif
}

static inline int far_stack_pop(FarStack* stack, uint* node, float* t_hi) {
  if (far_stack_is_empty(stack)) return 0;
#if MBAO_TRAVERSAL == MBAO_TRAVERSAL_STACK
  --stack->top;
#else
  stack->top = (stack->top - 1) & (MBAO_STACK_SIZE - 1);
  --stack->count;
#endif
  const uint2 entry = stack->entries[stack->top];
  *node = entry.x;
  *t_hi = as_float(entry.y);
  return 1;
}
#endif

// Finds the closest hit with 0 < t <= t_max (ties go to the lower triangle id),
// or with any_hit, any hit in that range. Returns 1 on a hit; *hit is no_hit()
// on a miss.
//
// A descent step picks its child and pushes with selects, not with if/else on
// the ray's data: AO rays take either side of a split at random, and such
// branches go wrong about every other step. With MBAO_LOAD_BOTH_CHILDREN (the
// full stack on CPUs) it also loads both children before the choice, so that
// the next node's fetch overlaps the step's arithmetic instead of following it
// (docs/traversal-on-pocl.md has the measurements).
static inline int trace_ray(const SceneView* scene, float3 origin, float3 dir, float t_max,
                            int any_hit, Hit* hit, TraversalCounts* counts) {
  *hit = no_hit();
  // From +0 where a component is -0: the descent reads which way the ray heads
  // from the sign of inv_dir, so a ray that does not move along an axis counts
  // as heading up there, whatever the sign of its zero, and a ray lying in a
  // split plane (t_split NaN) goes below.
  const float3 inv_dir = 1.0f / (dir + 0.0f);
  float t_enter, t_exit;
  if (!clip_to_box(origin, dir, inv_dir, scene->bounds_lo, scene->bounds_hi, t_max, &t_enter,
                   &t_exit))
    return 0;
  const WatertightRay ray = make_watertight_ray(origin, dir, scene->bounds_lo, scene->bounds_hi);
  // Per axis, for the descent: the origin and 1 / dir in one vector that a
  // step loads by its axis. Picking a vector component by a run-time axis
  // costs a chain of selects; separate arrays cost a load each, and the
  // compiler kept their addresses in spill slots. The sign of 1 / dir says
  // whether the ray heads down: dir + 0 is never -0.
  const float2 axis_ray[3] = {(float2)(origin.x, inv_dir.x), (float2)(origin.y, inv_dir.y),
                              (float2)(origin.z, inv_dir.z)};

  Hit best = no_hit();
  best.t = t_max;
  uint start_node = 0;
  float t_lo = t_enter;
  uint resumed = 0;  // past the first leaf: zero-length intervals may be skipped
#if MBAO_STACK_SIZE > 0
  uint2 far_entries[MBAO_STACK_SIZE + 1];
  FarStack stack = {far_entries, 0, 0};
#endif
  for (;;) {
    uint index;
    float t_hi;
    uint whole_interval_inside;  // so far, the walk's whole remaining interval lies in `index`'s cell
#if MBAO_STACK_SIZE > 0
    if (far_stack_pop(&stack, &index, &t_hi)) {
      whole_interval_inside = 0;
    } else
#endif
    {
      index = start_node;
      t_hi = t_exit;
      whole_interval_inside = 1;
      if (resumed) MBAO_COUNT(counts, restarts, 1);
    }

    // A step sends the walk to the far child alone where the plane lies behind
    // the ray or at the interval's start (there only past the first leaf):
    // with t_lo >= 0, where t_split <= 0 or t_split < t_lo (t_split at most the
    // float below t_lo) on the first descent, and where t_split <= t_lo after
    // it. Either way one compare with far_bound.
    const float far_bound = resumed ? t_lo : t_lo > 0.0f ? as_float(as_uint(t_lo) - 1u) : 0.0f;
    KdNode node = scene->nodes[index];
    MBAO_COUNT(counts, nodes, 1);
    while (!kd_is_leaf(node)) {
      const float2 along_axis = axis_ray[kd_axis(node)];
      const float t_split = (kd_split(node) - along_axis.x) * along_axis.y;
      const uint below = index + 1;
      const uint above = kd_above_child(node);
      const uint heads_down = (uint)(as_int(along_axis.y) >> 31);  // all bits set or none
      const uint swap = (below ^ above) & heads_down;
      const uint near = below ^ swap, far = above ^ swap;
      // To the near child alone where the plane lies beyond the interval, or
      // where t_split is NaN: a ray lying in the plane, which +0 sends below.
      const uint far_only = t_split <= far_bound;
      const uint both = !far_only & (t_split <= t_hi);
#if MBAO_STACK_SIZE > 0
      far_stack_push_if(&stack, both, far, t_hi);
#endif
      t_hi = both ? t_split : t_hi;
      whole_interval_inside &= !both;
      index = far_only ? far : near;
#if MBAO_PUSH_DOWN
      start_node = whole_interval_inside ? index : start_node;
#endif
#if MBAO_LOAD_BOTH_CHILDREN
      // volatile: otherwise the compiler turns the choice between two loaded
      // nodes back into one load of the chosen node. As words, not as KdNode:
      // a volatile struct is copied through memory.
      volatile __global const uint2* node_words = (volatile __global const uint2*)scene->nodes;
      const uint2 below_words = node_words[below], above_words = node_words[above];
      const uint2 words = index == below ? below_words : above_words;
      node.header = words.x;
      node.payload = words.y;
#else
      node = scene->nodes[index];
#endif
      MBAO_COUNT(counts, nodes, 1);
    }

    MBAO_COUNT(counts, leaves, 1);
    if (test_leaf(scene, &ray, node, any_hit, &best, counts)) break;
    if (best.triangle != MBAO_NO_TRIANGLE && best.t <= t_hi) break;
    t_lo = t_hi;
    resumed = 1;
#if MBAO_STACK_SIZE > 0
    if (far_stack_is_empty(&stack) && t_lo >= t_exit) break;
#else
    if (t_lo >= t_exit) break;
#endif
  }

  if (best.triangle == MBAO_NO_TRIANGLE) return 0;
  *hit = best;
  return 1;
}

#endif
