// kd-tree traversal, in the four ways of MBAO_TRAVERSAL:
//   restart     (Foley and Sugerman 2005): no stack; every leaf after the first
//               is found by a new descent from the root;
//   push-down   (Horn et al. 2007): no stack; a new descent starts at the
//               deepest node whose cell held the whole remaining interval;
//   short stack (Horn et al. 2007): push-down plus a small circular stack of
//               far children; a descent restarts only when the stack runs dry;
//   stack       a stack as deep as the tree: every node is visited once;
//   lanes       the full stack, sixteen rays per work item (kd_lanes.h): kernels
//               that trace streams of rays walk them so, the camera rays walk
//               sixteen to a packet (kd_packet.h), the rest as "stack".
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
#include "mbao/traversal.h"
#include "scene.h"

#ifndef MBAO_TRAVERSAL
#define MBAO_TRAVERSAL MBAO_TRAVERSAL_PUSHDOWN
#endif

// Each walk's stack: its entries (the short stack's a power of two: it wraps
// around), whether it is as deep as the tree (it never wraps) and whether
// descents remember a push-down node. A lanes program walks its rays of one
// per work item (ray queries, HBAO's G-buffer) as the full stack.
#if MBAO_TRAVERSAL == MBAO_TRAVERSAL_RESTART
#define MBAO_STACK_SIZE 0
#define MBAO_FULL_STACK 0
#define MBAO_PUSH_DOWN 0
#elif MBAO_TRAVERSAL == MBAO_TRAVERSAL_PUSHDOWN
#define MBAO_STACK_SIZE 0
#define MBAO_FULL_STACK 0
#define MBAO_PUSH_DOWN 1
#elif MBAO_TRAVERSAL == MBAO_TRAVERSAL_SHORT_STACK
#ifndef MBAO_SHORT_STACK_SIZE
#define MBAO_SHORT_STACK_SIZE 4
#endif
#define MBAO_STACK_SIZE MBAO_SHORT_STACK_SIZE
#define MBAO_FULL_STACK 0
#define MBAO_PUSH_DOWN 1
#elif MBAO_TRAVERSAL == MBAO_TRAVERSAL_STACK || MBAO_TRAVERSAL == MBAO_TRAVERSAL_LANES
#define MBAO_STACK_SIZE MBAO_KD_MAX_DEPTH
#define MBAO_FULL_STACK 1
#define MBAO_PUSH_DOWN 0
#else
#error "MBAO_TRAVERSAL must be one of MBAO_TRAVERSAL_RESTART .. MBAO_TRAVERSAL_LANES"
#endif

// What a walk cost, counted only in programs built with MBAO_COUNT_TRAVERSAL.
typedef struct TraversalCounts {
  uint nodes;  // nodes fetched, interior and leaf
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
#ifndef MBAO_ORIGIN_PATHS
#define MBAO_ORIGIN_PATHS 0
#endif
#if MBAO_COUNT_TRAVERSAL
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#define MBAO_COUNT(counts, field, n) ((counts)->field += (n))
#else
#define MBAO_COUNT(counts, field, n) ((void)0)
#endif

// Adds a work item's counts to the frame's four totals; nothing in programs
// that do not count, which need no 64-bit atomics.
static inline void add_traversal_counts(__global ulong* totals, const TraversalCounts* counts) {
#if MBAO_COUNT_TRAVERSAL
  atom_add(&totals[0], (ulong)counts->nodes);
  atom_add(&totals[1], (ulong)counts->leaves);
  atom_add(&totals[2], (ulong)counts->triangles);
  atom_add(&totals[3], (ulong)counts->restarts);
#endif
}

static inline TraversalCounts no_traversal_counts(void) {
  TraversalCounts counts = {0, 0, 0, 0};
  return counts;
}

// Tests the triangles of a leaf against the ray, keeping the closest hit in
// *best (ties to the lower triangle id). Returns 1 when any_hit and a hit was found.
static inline int test_leaf(const SceneView* scene, const WatertightRay* ray, KdNode leaf, int any_hit, Hit* best,
                            TraversalCounts* counts) {
  const uint first_entry = kd_first_index(leaf);
  const uint end_entry = first_entry + kd_triangle_count(leaf);
  MBAO_COUNT(counts, triangles, end_entry - first_entry);
  for (uint entry = first_entry; entry < end_entry; ++entry) {
    const uint entry_word = scene->leaf_entries[entry], triangle = kd_entry_triangle(entry_word);
    MBAO_TRIANGLE_AT(corners, scene, triangle);
    float t, b1, b2;
    if (!intersect_triangle(ray, corners, best->t, &t, &b1, &b2) ||
        (kd_entry_masked(entry_word) && !hit_is_solid(scene, triangle, b1, b2)))
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

// The far children a descent passed by, each with the end of its interval. Its
// start need not be kept: the intervals of the leaves a walk visits follow one
// another, so a popped child's interval starts where the leaf before it ended,
// which is where the walk stands. The entries, (node, t_hi bits), lie in an
// array the walk declares, one slot more than the stack holds, written by the
// steps that push nothing (a descent step does not branch on whether it
// pushes). The array is not a member: beside an array indexed at run time the
// compiler left the counters in memory, and every step waited on a store and
// a load of `top` (docs/traversal.md). Restart and push-down keep none.
typedef struct FarStack {
  __private uint2* entries;
  uint top;    // next free slot
  uint count;  // entries held by the short stack, which overwrites its oldest (the full stack's is top)
} FarStack;

static inline void far_stack_push_if(FarStack* stack, uint push, uint node, float t_hi) {
  if (MBAO_STACK_SIZE == 0) return;
  uint slot;
  if (MBAO_FULL_STACK) {
    // It holds at most one entry per tree level, so top never passes the spare slot.
    slot = stack->top;
    stack->top += push;
  } else {
    slot = push ? stack->top : MBAO_STACK_SIZE;
    stack->top = (stack->top + push) & (MBAO_STACK_SIZE - 1);
    stack->count = min(stack->count + push, (uint)MBAO_STACK_SIZE);
  }
  stack->entries[slot] = (uint2)(node, as_uint(t_hi));
}

// Without a stack (restart, push-down) it is always empty, and the compiler
// drops the pops.
static inline int far_stack_is_empty(const FarStack* stack) {
  if (MBAO_STACK_SIZE == 0) return 1;
  return (MBAO_FULL_STACK ? stack->top : stack->count) == 0;
}

static inline int far_stack_pop(FarStack* stack, uint* node, float* t_hi) {
  if (far_stack_is_empty(stack)) return 0;
  if (MBAO_FULL_STACK) {
    --stack->top;
  } else {
    stack->top = (stack->top - 1) & (MBAO_STACK_SIZE - 1);
    --stack->count;
  }
  const uint2 entry = stack->entries[stack->top];
  *node = entry.x;
  *t_hi = as_float(entry.y);
  return 1;
}

// What a descent carries from step to step.
typedef struct Descent {
  float t_hi;                  // the end of the interval still to walk in the current node
  float far_bound;             // a plane at or before this distance sends the walk to the far child alone
  uint whole_interval_inside;  // so far, the walk's whole remaining interval lies in the current node's cell
  uint start_node;             // push-down: where the next descent starts
} Descent;

// One step down from interior node `node` (at `index`): returns the child the
// walk goes on in and pushes the far child where the interval reaches both.
//
// A step picks its child and pushes with selects, not with if/else on the ray's
// data: AO rays take either side of a split at random, and such branches go
// wrong about every other step. The plane lies behind the ray or at the
// interval's start where t_split <= far_bound: with t_lo >= 0, where t_split <= 0
// or t_split < t_lo (t_split at most the float below t_lo) on a walk's first
// descent, and where t_split <= t_lo after it.
static inline uint descent_step(const float2* axis_ray, KdNode node, uint index, Descent* d, FarStack* stack) {
  const float2 along_axis = axis_ray[kd_axis(node)];
  const float t_split = (kd_split(node) - along_axis.x) * along_axis.y;
  const uint below = index + 1;
  const uint above = kd_above_child(node);
  const uint heads_down = (uint)(as_int(along_axis.y) >> 31);  // all bits set or none
  const uint swap = (below ^ above) & heads_down;
  const uint near = below ^ swap, far = above ^ swap;
  // To the near child alone where the plane lies beyond the interval, or
  // where t_split is NaN: a ray lying in the plane, which +0 sends below.
  const uint far_only = t_split <= d->far_bound;
  const uint both = !far_only & (t_split <= d->t_hi);
  far_stack_push_if(stack, both, far, d->t_hi);
  d->t_hi = both ? t_split : d->t_hi;
  d->whole_interval_inside &= !both;
  const uint next = far_only ? far : near;
  if (MBAO_PUSH_DOWN) d->start_node = d->whole_interval_inside ? next : d->start_node;
  return next;
}

// The interior nodes from the root down to the leaf whose cell holds a point
// that several rays leave from (the r rays of an AO surface). A walk's first
// descent from that point passes the same nodes whatever the ray's direction
// (at each, the child that holds the point), so with MBAO_ORIGIN_PATHS (CPUs)
// it takes them from here, at hand, instead of fetching one after another from
// the tree, each fetch waiting on the one before. The walk checks every child
// it takes against the path and goes back to the tree where they part, so a
// path changes where nodes come from, never a hit. They part only where the
// point lies on a plane, where the path stops: there the direction decides.
// A path holds the first MBAO_ORIGIN_PATH_STEPS steps, as deep as the shared
// scenes' trees go (at most 31), not MBAO_KD_MAX_DEPTH: a work item keeps a
// path for every bounce level.
#define MBAO_ORIGIN_PATH_STEPS 32
typedef struct OriginPath {
  KdNode steps[MBAO_ORIGIN_PATH_STEPS];  // the interior nodes passed, root first
  uint went_below;                       // bit k: the child below steps[k] holds the point
  uint length;                           // steps held: 0 for a point without a path
} OriginPath;

// The point several rays leave from, with its path in programs built with MBAO_ORIGIN_PATHS.
typedef struct RayOrigin {
  float3 point;
#if MBAO_ORIGIN_PATHS
  OriginPath path;
#endif
} RayOrigin;

// A ray origin whose rays walk from the root: for a point only one ray leaves.
static inline void set_ray_origin(float3 point, RayOrigin* origin) {
  origin->point = point;
#if MBAO_ORIGIN_PATHS
  origin->path.length = 0;
#endif
}

// A ray origin for several rays: with MBAO_ORIGIN_PATHS its path is found here, once for them all.
static inline void locate_ray_origin(const SceneView* scene, float3 point, RayOrigin* origin) {
  set_ray_origin(point, origin);
#if MBAO_ORIGIN_PATHS
  const float coordinate[3] = {point.x, point.y, point.z};
  OriginPath* path = &origin->path;
  uint index = 0, length = 0, went_below = 0;
  KdNode node = scene->nodes[0];
  while (!kd_is_leaf(node) && length < MBAO_ORIGIN_PATH_STEPS) {
    // The difference descent_step computes: zero where the point is on the plane.
    const float to_plane = kd_split(node) - coordinate[kd_axis(node)];
    if (to_plane == 0.0f) break;
    const uint below = to_plane > 0.0f;
    path->steps[length] = node;
    went_below |= below << length;
    ++length;
    index = below ? index + 1 : kd_above_child(node);
    node = scene->nodes[index];
  }
  path->went_below = went_below;
  path->length = length;
#endif
}

// A walk's first descent from the root along the origin's path, for as long
// as the children it takes are the path's: returns the node it stands at
// after. Without origin paths it stands at the root.
static inline uint descend_from_origin(const RayOrigin* origin, const float2* axis_ray, Descent* d, FarStack* stack,
                                       TraversalCounts* counts) {
  uint index = 0;
#if MBAO_ORIGIN_PATHS
  const OriginPath* path = &origin->path;
  for (uint k = 0; k < path->length; ++k) {
    const KdNode node = path->steps[k];
    const uint next = descent_step(axis_ray, node, index, d, stack);
    const uint on_path = (path->went_below >> k) & 1 ? index + 1 : kd_above_child(node);
    MBAO_COUNT(counts, nodes, 1);
    index = next;
    if (next != on_path) break;
  }
#endif
  return index;
}

// Finds the closest hit with 0 < t <= t_max (ties go to the lower triangle id),
// or with any_hit, any hit in that range, for the ray from origin->point along
// dir. Returns 1 on a hit; *hit is no_hit() on a miss.
//
// With MBAO_LOAD_BOTH_CHILDREN (the full stack on CPUs) a step also loads both
// children before the choice, so that the next node's fetch overlaps the step's
// arithmetic instead of following it (docs/traversal.md has the
// measurements). They are written out in the loop: in a function of their own
// they made Sponza's frames 1.03 and 1.07 of these (two runs of paired frames).
static inline int trace_ray_from(const SceneView* scene, const RayOrigin* origin, float3 dir, float t_max, int any_hit,
                                 Hit* hit, TraversalCounts* counts) {
  *hit = no_hit();
  const float3 point = origin->point;
  // From +0 where a component is -0: the descent reads which way the ray heads
  // from the sign of inv_dir, so a ray that does not move along an axis counts
  // as heading up there, whatever the sign of its zero, and a ray lying in a
  // split plane (t_split NaN) goes below.
  const float3 inv_dir = 1.0f / (dir + 0.0f);
  float t_enter, t_exit;
  if (!clip_to_box(point, dir, inv_dir, scene->bounds_lo, scene->bounds_hi, t_max, &t_enter, &t_exit)) return 0;
  const WatertightRay ray = make_watertight_ray(point, dir, scene->bounds_lo, scene->bounds_hi);
  // Per axis, for the descent: the origin and 1 / dir in one vector that a
  // step loads by its axis. Picking a vector component by a run-time axis
  // costs a chain of selects; separate arrays cost a load each, and the
  // compiler kept their addresses in spill slots. The sign of 1 / dir says
  // whether the ray heads down: dir + 0 is never -0.
  const float2 axis_ray[3] = {(float2)(point.x, inv_dir.x), (float2)(point.y, inv_dir.y), (float2)(point.z, inv_dir.z)};

  Hit best = no_hit();
  best.t = t_max;
  float t_lo = t_enter;
  uint resumed = 0;  // past the first leaf: zero-length intervals may be skipped
  Descent d;
  d.start_node = 0;
  uint2 far_entries[MBAO_STACK_SIZE + 1];
  FarStack stack = {far_entries, 0, 0};
  for (;;) {
    uint index;
    d.whole_interval_inside = 1;
    if (far_stack_pop(&stack, &index, &d.t_hi)) {
      d.whole_interval_inside = 0;
    } else {
      index = d.start_node;
      d.t_hi = t_exit;
      if (resumed) MBAO_COUNT(counts, restarts, 1);
    }
    d.far_bound = resumed ? t_lo : t_lo > 0.0f ? as_float(as_uint(t_lo) - 1u) : 0.0f;
    if (!resumed) index = descend_from_origin(origin, axis_ray, &d, &stack, counts);

    KdNode node = scene->nodes[index];
    MBAO_COUNT(counts, nodes, 1);
    while (!kd_is_leaf(node)) {
      const uint below = index + 1, above = kd_above_child(node);  // read only with MBAO_LOAD_BOTH_CHILDREN
      index = descent_step(axis_ray, node, index, &d, &stack);
      if (MBAO_LOAD_BOTH_CHILDREN) {
        // volatile: otherwise the compiler turns the choice between two loaded
        // nodes back into one load of the chosen node. As words, not as KdNode:
        // a volatile struct is copied through memory.
        volatile __global const uint2* node_words = (volatile __global const uint2*)scene->nodes;
        const uint2 below_words = node_words[below], above_words = node_words[above];
        const uint2 words = index == below ? below_words : above_words;
        node.header = words.x;
        node.payload = words.y;
      } else {
        node = scene->nodes[index];
      }
      MBAO_COUNT(counts, nodes, 1);
    }

    MBAO_COUNT(counts, leaves, 1);
    if (test_leaf(scene, &ray, node, any_hit, &best, counts)) break;
    if (best.triangle != MBAO_NO_TRIANGLE && best.t <= d.t_hi) break;
    t_lo = d.t_hi;
    resumed = 1;
    if (far_stack_is_empty(&stack) && t_lo >= t_exit) break;
  }

  if (best.triangle == MBAO_NO_TRIANGLE) return 0;
  *hit = best;
  return 1;
}

// A ray of its own, from the root.
static inline int trace_ray(const SceneView* scene, float3 origin, float3 dir, float t_max, int any_hit, Hit* hit,
                            TraversalCounts* counts) {
  RayOrigin from;
  set_ray_origin(origin, &from);
  return trace_ray_from(scene, &from, dir, t_max, any_hit, hit, counts);
}

#endif
