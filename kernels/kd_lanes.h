// The full-stack walk of kd_traversal.h, sixteen rays at a time in the lanes of
// one work item: traversal "lanes", for CPUs.
//
// PoCL runs a work group's items one after another and does not vectorise a
// walk whose steps branch, so a core walking one ray waits on each node fetch
// before the next. Here a step fetches the sixteen lanes' nodes as independent
// loads, in flight together, and does its arithmetic once for all sixteen in
// vector registers; pushes and leaves go lane by lane. A lane whose ray ends
// takes the next ray of the work item's range, so the lanes stay full to the
// end of it. The hits are trace_ray_from's with the full stack, bit for bit:
// every lane takes the same steps in the same order (tests/test_traversal.py).
// docs/traversal.md has the measurements behind each choice.
#ifndef MBAO_KD_LANES_H
#define MBAO_KD_LANES_H

#include "kd_traversal.h"

// Rays in, hits out, one slot per ray.
typedef struct RayStream {
  __global const float4* origins;
  __global const float4* directions;  // .w: t_max; negative for a slot with no ray (no interval survives the clip)
  __global uint4* hits;               // (t, triangle, b1, b2) bits, as trace_rays stores them
  __global uint4* ray_counts;         // per ray: nodes, leaves, triangle tests, restarts; NULL: not kept
} RayStream;

// An array over the lanes, aligned for lane_floats and lane_uints.
#define MBAO_LANE_ARRAY(type, name) type name[MBAO_LANES] __attribute__((aligned(64)))

// What each lane walks, as arrays over the lanes that a step loads as vectors.
typedef struct Lanes {
  float origin_x[MBAO_LANES], origin_y[MBAO_LANES], origin_z[MBAO_LANES];
  float inv_dir_x[MBAO_LANES], inv_dir_y[MBAO_LANES], inv_dir_z[MBAO_LANES];
  float t_lo[MBAO_LANES], t_hi[MBAO_LANES];  // the interval walked in the current node
  float t_exit[MBAO_LANES];                  // where the ray leaves the scene's box
  uint node[MBAO_LANES];                     // index of the node the lane stands at
  uint resumed[MBAO_LANES];                  // all bits set past the first leaf, else 0
  uint top[MBAO_LANES];                      // entries on the lane's stack
  uint ray[MBAO_LANES];                      // the lane's slot in the stream
  Hit best[MBAO_LANES];
  WatertightRay watertight[MBAO_LANES];
#if MBAO_COUNT_TRAVERSAL
  TraversalCounts counts[MBAO_LANES];
#endif
} __attribute__((aligned(64))) Lanes;  // so that its lane arrays are aligned

#if MBAO_COUNT_TRAVERSAL
#define MBAO_LANE_COUNTS(lanes, k) (&(lanes)->counts[k])
#else
#define MBAO_LANE_COUNTS(lanes, k) ((TraversalCounts*)0)  // never dereferenced: MBAO_COUNT does nothing
#endif

// Lane k holds bit k.
static inline uint16 lane_bit_values(void) {
  return (uint16)(1u << 0, 1u << 1, 1u << 2, 1u << 3, 1u << 4, 1u << 5, 1u << 6, 1u << 7, 1u << 8, 1u << 9, 1u << 10,
                  1u << 11, 1u << 12, 1u << 13, 1u << 14, 1u << 15);
}

// Bit k set where lane k of `mask` is true. Vector operations, not a loop over
// the lanes: PoCL turned that loop into sixteen extracts and branches.
static inline uint lane_bits(int16 mask) {
  const uint16 set = as_uint16(mask) & lane_bit_values();
  const uint8 in_8 = set.lo | set.hi;
  const uint4 in_4 = in_8.lo | in_8.hi;
  const uint2 in_2 = in_4.lo | in_4.hi;
  return in_2.x | in_2.y;
}

// The index of the lowest set bit of `bits` (not 0), as the count of the bits
// below it: ctz is OpenCL C 2.0, which compilers of OpenCL C 1.2 need not know.
// LLVM makes this one tzcnt.
static inline uint lowest_lane(uint bits) { return popcount(~bits & (bits - 1u)); }

// Lane k of the mask wherever bit k of `bits` is set (lane_bits undone).
static inline int16 lane_mask(uint bits) { return ((uint16)(bits)&lane_bit_values()) != 0u; }

static inline uint16 lane_indices(void) {
  return (uint16)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 10u, 11u, 12u, 13u, 14u, 15u);
}

// A lane array (64-byte aligned) as one vector: PoCL compiled vload16 from an
// array to eight 8-byte loads.
static inline float16 lane_floats(const float* lanes) { return *(const float16*)lanes; }
static inline uint16 lane_uints(const uint* lanes) { return *(const uint16*)lanes; }
static inline void set_lane_floats(float* lanes, float16 v) { *(float16*)lanes = v; }
static inline void set_lane_uints(uint* lanes, uint16 v) { *(uint16*)lanes = v; }

// The hit of lane k's ray (a miss where the ray found none) into its slot.
static inline void lanes_store_hit(const RayStream* stream, const Lanes* lanes, uint k, TraversalCounts* totals) {
  const Hit best = lanes->best[k].triangle == MBAO_NO_TRIANGLE ? no_hit() : lanes->best[k];
  stream->hits[lanes->ray[k]] = bits_of_hit(best);
#if MBAO_COUNT_TRAVERSAL
  const TraversalCounts c = lanes->counts[k];
  if (stream->ray_counts) stream->ray_counts[lanes->ray[k]] = (uint4)(c.nodes, c.leaves, c.triangles, c.restarts);
  totals->nodes += c.nodes;
  totals->leaves += c.leaves;
  totals->triangles += c.triangles;
  totals->restarts += c.restarts;
#endif
}

// Puts the ray in slot i into lane k; returns 0, with a miss stored, where
// there is no ray or it misses the scene's box.
static inline int lanes_take_ray(const SceneView* scene, const RayStream* stream, uint i, uint k, Lanes* lanes,
                                 TraversalCounts* totals) {
  const float3 point = stream->origins[i].xyz;
  const float4 direction = stream->directions[i];
  const float3 dir = direction.xyz;
  const float3 inv_dir = 1.0f / (dir + 0.0f);  // as in trace_ray_from: never -0
  lanes->ray[k] = i;
  lanes->best[k] = no_hit();
  lanes->best[k].t = direction.w;
#if MBAO_COUNT_TRAVERSAL
  lanes->counts[k] = no_traversal_counts();
#endif
  float t_enter, t_exit;
  if (!clip_to_box(point, dir, inv_dir, scene->bounds_lo, scene->bounds_hi, direction.w, &t_enter, &t_exit)) {
    lanes_store_hit(stream, lanes, k, totals);
    return 0;
  }
  lanes->origin_x[k] = point.x;
  lanes->origin_y[k] = point.y;
  lanes->origin_z[k] = point.z;
  lanes->inv_dir_x[k] = inv_dir.x;
  lanes->inv_dir_y[k] = inv_dir.y;
  lanes->inv_dir_z[k] = inv_dir.z;
  lanes->t_lo[k] = t_enter;
  lanes->t_hi[k] = t_exit;
  lanes->t_exit[k] = t_exit;
  lanes->node[k] = 0;
  lanes->resumed[k] = 0;
  lanes->top[k] = 0;
  lanes->watertight[k] = make_watertight_ray(point, dir, scene->bounds_lo, scene->bounds_hi);
  return 1;
}

// Fills lane k with the next ray of [*next, end) that enters the scene's box;
// returns 0 when none is left.
static inline int lanes_take_next(const SceneView* scene, const RayStream* stream, uint* next, uint end, uint k,
                                  Lanes* lanes, TraversalCounts* totals) {
  while (*next < end)
    if (lanes_take_ray(scene, stream, (*next)++, k, lanes, totals)) return 1;
  return 0;
}

// A walk's first descent sends a lane to the far child alone where the plane
// lies at or before this: the far_bound of trace_ray_from, on vectors.
static inline float16 first_descent_far_bound(float16 t_lo) {
  return select((float16)(0.0f), as_float16(as_uint16(t_lo) - 1u), t_lo > 0.0f);
}

// One descent step of every lane that stands at an interior node (descent_step
// on vectors), with the nodes the lanes stand at in header/payload. Far children
// are pushed for the `live` lanes only; the others' steps are discarded.
static inline void lanes_descend(Lanes* lanes, const uint* header, const uint* payload, uint live,
                                 __private ulong* stack) {
  const uint16 index = lane_uints(lanes->node), node_header = lane_uints(header);
  const float16 t_lo = lane_floats(lanes->t_lo), t_hi = lane_floats(lanes->t_hi);
  const uint16 axis = node_header & 3u;
  const int16 on_y = axis == 1u, on_z = axis == 2u;
  const float16 origin = select(select(lane_floats(lanes->origin_x), lane_floats(lanes->origin_y), on_y),
                                lane_floats(lanes->origin_z), on_z);
  const float16 inv_dir = select(select(lane_floats(lanes->inv_dir_x), lane_floats(lanes->inv_dir_y), on_y),
                                 lane_floats(lanes->inv_dir_z), on_z);
  const float16 t_split = (as_float16(lane_uints(payload)) - origin) * inv_dir;
  const uint16 below = index + 1u, above = node_header >> 2;
  const uint16 swap = (below ^ above) & as_uint16(as_int16(inv_dir) >> 31);
  const uint16 near = below ^ swap, far = above ^ swap;
  const int16 resumed = as_int16(lane_uints(lanes->resumed));
  const float16 far_bound = select(first_descent_far_bound(t_lo), t_lo, resumed);
  const int16 far_only = t_split <= far_bound;
  const int16 steps = axis != MBAO_KD_LEAF;
  const int16 both = steps & ~far_only & (t_split <= t_hi);
  set_lane_uints(lanes->node, select(index, select(near, far, far_only), steps));
  set_lane_floats(lanes->t_hi, select(t_hi, t_split, both));

  // Every lane writes its far child into the free slot above its stack, and
  // the lanes that push raise their tops: sixteen stores without a branch,
  // where a loop over the pushing lanes mispredicted its exit every step. The
  // entries go as 64-bit words from a vector in registers: read back from an
  // array of their halves, each waited for the array's stores to complete.
  const ulong16 entries = upsample(as_uint16(t_hi), far);
  const uint16 top = lane_uints(lanes->top);
  const uint16 slots = top * MBAO_LANES + lane_indices();
  // Lane by lane as components, written out: a vector indexed by a loop
  // counter is a clang extension, not OpenCL C.
#define MBAO_PUSH_LANE(k) stack[slots.s##k] = entries.s##k
  MBAO_PUSH_LANE(0), MBAO_PUSH_LANE(1), MBAO_PUSH_LANE(2), MBAO_PUSH_LANE(3);
  MBAO_PUSH_LANE(4), MBAO_PUSH_LANE(5), MBAO_PUSH_LANE(6), MBAO_PUSH_LANE(7);
  MBAO_PUSH_LANE(8), MBAO_PUSH_LANE(9), MBAO_PUSH_LANE(a), MBAO_PUSH_LANE(b);
  MBAO_PUSH_LANE(c), MBAO_PUSH_LANE(d), MBAO_PUSH_LANE(e), MBAO_PUSH_LANE(f);
#undef MBAO_PUSH_LANE
  set_lane_uints(lanes->top, top - as_uint16(both & lane_mask(live)));
}

// Lane k's leaf, as trace_ray_from's walk takes it: returns 1 where the ray is
// done, else moves the lane to where its walk goes on.
static inline int lanes_visit_leaf(const SceneView* scene, Lanes* lanes, uint k, KdNode leaf, int any_hit,
                                   __private const ulong* stack) {
  TraversalCounts* counts = MBAO_LANE_COUNTS(lanes, k);
  MBAO_COUNT(counts, leaves, 1);
  if (test_leaf(scene, &lanes->watertight[k], leaf, any_hit, &lanes->best[k], counts)) return 1;
  const float leaf_end = lanes->t_hi[k];
  if (lanes->best[k].triangle != MBAO_NO_TRIANGLE && lanes->best[k].t <= leaf_end) return 1;
  if (lanes->top[k] == 0 && leaf_end >= lanes->t_exit[k]) return 1;
  lanes->t_lo[k] = leaf_end;
  lanes->resumed[k] = 0xFFFFFFFFu;
  if (lanes->top[k] > 0) {
    const ulong entry = stack[--lanes->top[k] * MBAO_LANES + k];
    lanes->node[k] = (uint)entry;
    lanes->t_hi[k] = as_float((uint)(entry >> 32));
  } else {
    lanes->node[k] = 0;
    lanes->t_hi[k] = lanes->t_exit[k];
    MBAO_COUNT(counts, restarts, 1);
  }
  return 0;
}

// On x86-64 only: NVIDIA's compiler has the built-in too, but refuses it a
// __global pointer.
#if defined(__x86_64__) && defined(__has_builtin)
#if __has_builtin(__builtin_prefetch)
#define MBAO_BUILTIN_PREFETCH 1
#endif
#endif

// Starts loading a node. PoCL 3.1 compiles OpenCL's prefetch() to nothing and
// __builtin_prefetch to prefetcht0; other compilers get prefetch().
static inline void prefetch_node(__global const uint2* node) {
#ifdef MBAO_BUILTIN_PREFETCH
  __builtin_prefetch(node);
#else
  prefetch(node, 1);
#endif
}

// Traces the stream's rays [first, end) in sixteen lanes, adding their counts
// to *totals in programs built with MBAO_COUNT_TRAVERSAL.
static void trace_in_lanes(const SceneView* scene, const RayStream* stream, uint first, uint end, int any_hit,
                           TraversalCounts* totals) {
  Lanes lanes;
  // Lane k's entry j at j * MBAO_LANES + k, (node, t_hi bits) in the low and
  // high word, with a slot above the deepest stack for lanes_descend's writes.
  ulong stack[(MBAO_KD_MAX_DEPTH + 1) * MBAO_LANES];
  uint next = first, live = 0;
  for (uint k = 0; k < MBAO_LANES; ++k) {
    lanes.node[k] = 0;  // lanes left empty still fetch a node, the root,
    lanes.top[k] = 0;   // and write into their stacks
    if (lanes_take_next(scene, stream, &next, end, k, &lanes, totals)) live |= 1u << k;
  }
  __global const uint2* node_words = (__global const uint2*)scene->nodes;
  while (live) {
    MBAO_LANE_ARRAY(uint, header);
    MBAO_LANE_ARRAY(uint, payload);
    // Written out so that the sixteen fetches are independent loads.
#pragma unroll
    for (uint k = 0; k < MBAO_LANES; ++k) {
      const uint2 words = node_words[lanes.node[k]];
      header[k] = words.x;
      payload[k] = words.y;
    }
#if MBAO_COUNT_TRAVERSAL
    for (uint lanes_left = live; lanes_left; lanes_left &= lanes_left - 1)
      ++lanes.counts[lowest_lane(lanes_left)].nodes;
#endif
    const int16 at_leaf = (lane_uints(header) & 3u) == MBAO_KD_LEAF;
    lanes_descend(&lanes, header, payload, live, stack);
    // The next step's nodes on their way before the leaves' tests, which can
    // fill the core's window for the sixteen loads at the top of the loop.
#pragma unroll
    for (uint k = 0; k < MBAO_LANES; ++k) prefetch_node(node_words + lanes.node[k]);
    for (uint leaves = live & lane_bits(at_leaf); leaves; leaves &= leaves - 1) {
      const uint k = lowest_lane(leaves);
      KdNode leaf;
      leaf.header = header[k];
      leaf.payload = payload[k];
      if (!lanes_visit_leaf(scene, &lanes, k, leaf, any_hit, stack)) continue;
      lanes_store_hit(stream, &lanes, k, totals);
      if (!lanes_take_next(scene, stream, &next, end, k, &lanes, totals)) live &= ~(1u << k);
    }
  }
}

// Both programs' kernel for streams of rays (mbao.trace with traversal "lanes",
// and the wavefront's bounces): work item j traces rays
// [j * rays_per_item, (j + 1) * rays_per_item) of the `count`. Programs built
// with MBAO_COUNT_TRAVERSAL keep each ray's counts in ray_counts and add them
// to traversal_totals, either of which may be NULL.
__kernel void trace_rays_in_lanes(MBAO_SCENE_PARAMS, __global const float4* origins, __global const float4* directions,
                                  uint count, int any_hit, uint rays_per_item, __global uint4* hits,
                                  __global uint4* ray_counts, __global ulong* traversal_totals) {
  const uint first = get_global_id(0) * rays_per_item;
  if (first >= count) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  const RayStream stream = {origins, directions, hits, ray_counts};
  TraversalCounts totals = no_traversal_counts();
  trace_in_lanes(&scene, &stream, first, min(first + rays_per_item, count), any_hit, &totals);
  if (traversal_totals) add_traversal_counts(traversal_totals, &totals);
}

#endif
