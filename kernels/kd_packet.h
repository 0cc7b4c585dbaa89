// Rays that leave one point, walked down the kd-tree as one packet of sixteen:
// traversal "lanes" takes the camera rays so (render.cl's trace_camera_packets).
//
// A camera ray walked alone waits on each node fetch before the next, and its
// neighbours fetch the same nodes after it. The sixteen rays of a 4 x 4 square
// of pixels go much the same way, so here one fetch serves them all: a step
// does its arithmetic for the sixteen in the lanes of one vector, and a leaf
// tests each of its triangles against the sixteen at once. kd_lanes.h's walk
// instead gives each lane a ray of its own, which suits AO rays: they share
// little of their ways.
//
// Each ray walks as trace_ray_from's full stack would walk it alone: the same
// nodes with the same intervals, so the same hit and counts, bit for bit
// (tests/test_camera_packets.py). The packet visits a node for the lanes whose
// walk goes there; the others wait. What keeps one stack enough is the common
// origin: a ray that goes on to both children of a node takes first the one on
// the origin's side of the plane (the plane lies ahead of it), the same child
// for every ray. A ray that takes one child only takes it now or after the
// packet has walked the other, which changes nothing for that ray: it still
// meets its own nodes in its own order.
#ifndef MBAO_KD_PACKET_H
#define MBAO_KD_PACKET_H

#include "kd_lanes.h"

// Each lane's ray for the watertight test: as vectors over the lanes, and as
// the scalar test takes it, for its double fallback.
typedef struct PacketFrames {
  uint16 kx, ky, kz;
  float16 origin_x, origin_y, origin_z;
  float16 shear_x, shear_y, shear_z;
  float16 edge_error;
  WatertightRay lane[MBAO_LANES];
} PacketFrames;

// A Hit per lane: the closest so far, or a triangle's.
typedef struct PacketHits {
  float16 t, b1, b2;
  uint16 triangle;
} PacketHits;

// Corner `corner`'s coordinate along each lane's `axis` (0, 1 or 2).
static inline float16 corner_along(MBAO_TRIANGLE_SPACE const TriangleCoordinates* t, uint16 axis, int corner) {
  MBAO_TRIANGLE_SPACE const float* along = (MBAO_TRIANGLE_SPACE const float*)t->along;
  return select(select((float16)(along[corner]), (float16)(along[4 + corner]), axis == 1u),
                (float16)(along[8 + corner]), axis == 2u);
}

// intersect_triangle for the `active` lanes against one triangle: per lane the
// same operations in the same order, so each lane's outcome is the scalar
// test's bit for bit. Returns the lanes that hit with t in (0, t_max] and their
// t, b1 and b2; a lane whose edge signs float leaves unknown (edge_errors)
// takes the scalar test with its double fallback instead.
static inline uint packet_intersect(const SceneView* scene, const PacketFrames* f, uint active, uint triangle,
                                    float16 t_max, PacketHits* out) {
  MBAO_TRIANGLE_AT(t, scene, triangle);
  float16 x[3], y[3], z[3];
  for (int c = 0; c < 3; ++c) {
    z[c] = corner_along(t, f->kz, c) - f->origin_z;
    x[c] = (corner_along(t, f->kx, c) - f->origin_x) - f->shear_x * z[c];
    y[c] = (corner_along(t, f->ky, c) - f->origin_y) - f->shear_y * z[c];
  }
  const float16 e0 = x[1] * y[2] - y[1] * x[2], e1 = x[2] * y[0] - y[2] * x[0], e2 = x[0] * y[1] - y[0] * x[1];
  const int16 outside = ((e0 < 0.0f) | (e1 < 0.0f) | (e2 < 0.0f)) & ((e0 > 0.0f) | (e1 > 0.0f) | (e2 > 0.0f));
  const float16 det = e0 + e1 + e2;
  const float16 inv_det = 1.0f / det;
  const float16 b0 = e0 * inv_det, b1 = e1 * inv_det, b2 = e2 * inv_det;
  const float16 t_hit = (b0 * z[0] + b1 * z[1] + b2 * z[2]) * f->shear_z;
  const int16 hit = ~outside & (det != 0.0f) & (t_hit > 0.0f) & (t_hit <= t_max);
  uint hits = active & lane_bits(hit);
  out->t = t_hit;
  out->b1 = b1;
  out->b2 = b2;
#if MBAO_USE_FP64
  const float16 across0 = fabs(x[0]) + fabs(y[0]), across1 = fabs(x[1]) + fabs(y[1]), across2 = fabs(x[2]) + fabs(y[2]);
  const int16 unknown = (fabs(e0) <= f->edge_error * (across1 + across2)) |
                        (fabs(e1) <= f->edge_error * (across2 + across0)) |
                        (fabs(e2) <= f->edge_error * (across0 + across1));
  uint redo = active & lane_bits(unknown);
  if (redo) {
    float lane_t[MBAO_LANES], lane_b1[MBAO_LANES], lane_b2[MBAO_LANES], lane_t_max[MBAO_LANES];
    vstore16(out->t, 0, lane_t);
    vstore16(out->b1, 0, lane_b1);
    vstore16(out->b2, 0, lane_b2);
    vstore16(t_max, 0, lane_t_max);
    for (; redo; redo &= redo - 1) {
      const uint k = lowest_lane(redo);
      const int hit_k = intersect_triangle(&f->lane[k], t, lane_t_max[k], &lane_t[k], &lane_b1[k], &lane_b2[k]);
      hits = hit_k ? hits | (1u << k) : hits & ~(1u << k);
    }
    out->t = vload16(0, lane_t);
    out->b1 = vload16(0, lane_b1);
    out->b2 = vload16(0, lane_b2);
  }
#endif
  return hits;
}

// The lanes of `hits` whose hit on the triangle of leaf entry `entry` its alpha
// mask does not cut away.
static inline uint packet_solid_hits(const SceneView* scene, uint entry, uint hits, const PacketHits* h) {
  if (!MBAO_ALPHA_MASKS || !hits || !kd_entry_masked(entry)) return hits;
  const uint triangle = kd_entry_triangle(entry);
  float b1[MBAO_LANES], b2[MBAO_LANES];
  vstore16(h->b1, 0, b1);
  vstore16(h->b2, 0, b2);
  for (uint lanes = hits; lanes; lanes &= lanes - 1) {
    const uint k = lowest_lane(lanes);
    if (!hit_is_solid(scene, triangle, b1[k], b2[k])) hits &= ~(1u << k);
  }
  return hits;
}

// test_leaf for the `active` lanes, closest hits: each lane keeps the hit
// with the smallest t, ties to the lower triangle id, as the scalar loop does
// whatever the order of the triangles.
static inline void packet_test_leaf(const SceneView* scene, const PacketFrames* f, KdNode leaf, uint active,
                                    PacketHits* best) {
  const uint first_entry = kd_first_index(leaf), end_entry = first_entry + kd_triangle_count(leaf);
  for (uint entry = first_entry; entry < end_entry; ++entry) {
    const uint entry_word = scene->leaf_entries[entry], triangle = kd_entry_triangle(entry_word);
    PacketHits h;
    const uint hits =
        packet_solid_hits(scene, entry_word, packet_intersect(scene, f, active, triangle, best->t, &h), &h);
    if (!hits) continue;
    const int16 better = lane_mask(hits) & ((h.t < best->t) | ((uint16)(triangle) < best->triangle));
    best->t = select(best->t, h.t, better);
    best->b1 = select(best->b1, h.b1, better);
    best->b2 = select(best->b2, h.b2, better);
    best->triangle = select(best->triangle, (uint16)(triangle), better);
  }
}

// Per lane what the walk cost (TraversalCounts per lane), kept only in programs
// built with MBAO_COUNT_TRAVERSAL.
typedef struct PacketCounts {
  uint16 nodes, leaves, triangles;  // a full stack never restarts
} PacketCounts;

#if MBAO_COUNT_TRAVERSAL
#define MBAO_PACKET_COUNT(counts, field, lanes, n) \
  ((counts)->field += select((uint16)(0u), (uint16)(n), lane_mask(lanes)))
#else
#define MBAO_PACKET_COUNT(counts, field, lanes, n) ((void)0)
#endif

static inline uint sum_of_lanes(uint16 v) {
  const uint8 v8 = v.lo + v.hi;
  const uint4 v4 = v8.lo + v8.hi;
  const uint2 v2 = v4.lo + v4.hi;
  return v2.x + v2.y;
}

// Where the walk of each lane stands: the interval it walks in the current
// node and what its descent compares planes with (Descent, per lane).
typedef struct PacketWalk {
  float16 inv_dir_x, inv_dir_y, inv_dir_z;
  float16 t_hi;       // the end of the lane's interval in the current node
  float16 far_bound;  // a plane at or before this sends the lane to the far child alone
  float16 t_exit;     // where the lane's ray leaves the scene's box
} PacketWalk;

// The far children the packet passed by: per entry the node, the lanes that go
// there and each one's interval end. A lane's own entries are a subsequence in
// the order its walk alone would push them, so popping the packet's entries
// pops each lane's in its own order. The entries are children of the current
// node's ancestors, one per tree level at most.
typedef struct PacketStack {
  uint node[MBAO_KD_MAX_DEPTH];
  uint lanes[MBAO_KD_MAX_DEPTH];
  float16 t_hi[MBAO_KD_MAX_DEPTH];
  uint top;
  uint16 entries;  // per lane, the entries on the stack that hold it
} PacketStack;

static inline void packet_push(PacketStack* stack, uint node, uint lanes, float16 t_hi) {
  stack->node[stack->top] = node;
  stack->lanes[stack->top] = lanes;
  stack->t_hi[stack->top] = t_hi;
  ++stack->top;
  stack->entries += select((uint16)(0u), (uint16)(1u), lane_mask(lanes));
}

// Pops entries until one holds a lane that is not done; returns those lanes
// (0: the stack is empty), moves the walk to its node and sets their t_hi.
static inline uint packet_pop(PacketStack* stack, uint done, uint* node, PacketWalk* w) {
  while (stack->top > 0) {
    const uint top = --stack->top;
    const uint lanes = stack->lanes[top];
    stack->entries -= select((uint16)(0u), (uint16)(1u), lane_mask(lanes));
    if (!(lanes & ~done)) continue;
    *node = stack->node[top];
    w->t_hi = select(w->t_hi, stack->t_hi[top], lane_mask(lanes & ~done));
    return lanes & ~done;
  }
  return 0;
}

// One step down from interior node `node` (at `index`) for the `*active`
// lanes, descent_step per lane: returns the child the packet goes on in, with
// the lanes that go there in *active, and pushes the other child for the lanes
// that go there now or after this one.
static inline uint packet_descend(float3 origin, PacketWalk* w, KdNode node, uint index, uint* active,
                                  PacketStack* stack) {
  const uint axis = kd_axis(node);
  const float along = axis == 0 ? origin.x : axis == 1 ? origin.y : origin.z;
  const float16 inv_dir = axis == 0 ? w->inv_dir_x : axis == 1 ? w->inv_dir_y : w->inv_dir_z;
  const float16 t_split = (kd_split(node) - along) * inv_dir;
  const int16 heads_down = as_int16(inv_dir) >> 31;
  const int16 far_only = t_split <= w->far_bound;
  const int16 both = ~far_only & (t_split <= w->t_hi);
  // The child a lane takes first: its near child (below unless it heads down), or its far one alone.
  const uint above_first = *active & lane_bits(far_only ^ heads_down), below_first = *active & ~above_first;
  const uint two = *active & lane_bits(both);
  // Lanes that take both children take the origin's side first, all the same one.
  const uint now_above = two ? (two & above_first) != 0 : below_first == 0;
  const uint below = index + 1, above = kd_above_child(node);
  const uint later = (now_above ? below_first : above_first) | two;
  if (later) packet_push(stack, now_above ? below : above, later, w->t_hi);
  w->t_hi = select(w->t_hi, t_split, lane_mask(two));
  *active = now_above ? above_first : below_first;
  return now_above ? above : below;
}

// Closest hits (t_max infinite) of the `rays` lanes' rays from `origin` along
// dir_x/y/z[k], each as trace_ray_from's full stack finds it, into
// hit_bits[k] as (t, triangle, b1, b2) bits; per-lane counts into *counts.
static void trace_packet(const SceneView* scene, float3 origin, const float* dir_x, const float* dir_y,
                         const float* dir_z, uint rays, uint4* hit_bits, PacketCounts* counts) {
  float inv_x[MBAO_LANES], inv_y[MBAO_LANES], inv_z[MBAO_LANES], t_enter[MBAO_LANES], t_exit[MBAO_LANES];
  uint kx[MBAO_LANES], ky[MBAO_LANES], kz[MBAO_LANES];
  float frame[7][MBAO_LANES];
  PacketFrames f;
  uint active = 0;
  for (uint k = 0; k < MBAO_LANES; ++k) {
    const float3 dir = (rays >> k) & 1 ? (float3)(dir_x[k], dir_y[k], dir_z[k]) : (float3)(0.0f, 0.0f, 1.0f);
    const float3 inv_dir = 1.0f / (dir + 0.0f);  // as in trace_ray_from: never -0
    inv_x[k] = inv_dir.x;
    inv_y[k] = inv_dir.y;
    inv_z[k] = inv_dir.z;
    if (clip_to_box(origin, dir, inv_dir, scene->bounds_lo, scene->bounds_hi, INFINITY, &t_enter[k], &t_exit[k]))
      active |= rays & (1u << k);
    const WatertightRay ray = make_watertight_ray(origin, dir, scene->bounds_lo, scene->bounds_hi);
    f.lane[k] = ray;
    kx[k] = ray.kx;
    ky[k] = ray.ky;
    kz[k] = ray.kz;
    frame[0][k] = ray.origin_x;
    frame[1][k] = ray.origin_y;
    frame[2][k] = ray.origin_z;
    frame[3][k] = ray.shear_x;
    frame[4][k] = ray.shear_y;
    frame[5][k] = ray.shear_z;
    frame[6][k] = ray.edge_error;
  }
  f.kx = vload16(0, kx);
  f.ky = vload16(0, ky);
  f.kz = vload16(0, kz);
  f.origin_x = vload16(0, frame[0]);
  f.origin_y = vload16(0, frame[1]);
  f.origin_z = vload16(0, frame[2]);
  f.shear_x = vload16(0, frame[3]);
  f.shear_y = vload16(0, frame[4]);
  f.shear_z = vload16(0, frame[5]);
  f.edge_error = vload16(0, frame[6]);
  PacketWalk w;
  w.inv_dir_x = vload16(0, inv_x);
  w.inv_dir_y = vload16(0, inv_y);
  w.inv_dir_z = vload16(0, inv_z);
  w.t_exit = vload16(0, t_exit);
  w.t_hi = w.t_exit;
  w.far_bound = first_descent_far_bound(vload16(0, t_enter));
  PacketHits best = {(float16)(INFINITY), (float16)(0.0f), (float16)(0.0f), (uint16)(MBAO_NO_TRIANGLE)};

  PacketStack stack;
  stack.top = 0;
  stack.entries = (uint16)(0u);
  uint done = ~active, index = 0;
  while (active || (active = packet_pop(&stack, done, &index, &w))) {
    const KdNode node = scene->nodes[index];
    MBAO_PACKET_COUNT(counts, nodes, active, 1u);
    if (!kd_is_leaf(node)) {
      index = packet_descend(origin, &w, node, index, &active, &stack);
      continue;
    }
    MBAO_PACKET_COUNT(counts, leaves, active, 1u);
    MBAO_PACKET_COUNT(counts, triangles, active, kd_triangle_count(node));
    packet_test_leaf(scene, &f, node, active, &best);
    // As after a leaf of trace_ray_from: done where the hit lies in it, or
    // where the lane has nothing pushed (its leaf then ends at t_exit: a full
    // stack never restarts); else on from where the leaf ends.
    const int16 ends = ((best.triangle != MBAO_NO_TRIANGLE) & (best.t <= w.t_hi)) | (stack.entries == 0u);
    done |= active & lane_bits(ends);
    w.far_bound = select(w.far_bound, w.t_hi, lane_mask(active));
    active = 0;
  }

  uint t_bits[MBAO_LANES], triangle[MBAO_LANES], b1_bits[MBAO_LANES], b2_bits[MBAO_LANES];
  vstore16(as_uint16(best.t), 0, t_bits);
  vstore16(best.triangle, 0, triangle);
  vstore16(as_uint16(best.b1), 0, b1_bits);
  vstore16(as_uint16(best.b2), 0, b2_bits);
  for (uint k = 0; k < MBAO_LANES; ++k)
    hit_bits[k] = triangle[k] == MBAO_NO_TRIANGLE ? bits_of_hit(no_hit())
                                                  : (uint4)(t_bits[k], triangle[k], b1_bits[k], b2_bits[k]);
}

#endif
