// The kd-tree node, on the host as on the device: 8 bytes, after pbrt's layout.
//   header, low 2 bits: split axis 0..2, or 3 for a leaf.
//   header, upper 30 bits: interior -> index of the child above the split
//                          (the child below is always the next node);
//                          leaf -> number of triangles.
//   payload: interior -> split position (float bits);
//            leaf -> where the leaf's entries start, counted in 32-bit words
//            from the start of the node array, where they follow the leaf's
//            node (cpp/accel/kd_tree.h).
#ifndef MBAO_KD_NODE_H
#define MBAO_KD_NODE_H

#include "mbao/platform.h"

typedef struct KdNode {
  mbao_u32 header;
  mbao_u32 payload;
} KdNode;

#define MBAO_KD_LEAF 3u
#define MBAO_KD_MAX_INDEX ((1u << 30) - 1u)

MBAO_FN KdNode kd_make_interior(mbao_u32 axis, float split, mbao_u32 above_child) {
  KdNode node;
  node.header = (above_child << 2) | axis;
  node.payload = mbao_float_as_u32(split);
  return node;
}

MBAO_FN KdNode kd_make_leaf(mbao_u32 triangle_count, mbao_u32 first_index) {
  KdNode node;
  node.header = (triangle_count << 2) | MBAO_KD_LEAF;
  node.payload = first_index;
  return node;
}

// A leaf's entry: the triangle id in the low 31 bits, the top bit set where
// the triangle has an alpha mask, so that a walk looks up the masks of those
// triangles only.
#define MBAO_KD_ENTRY_MASKED 0x80000000u

MBAO_FN int kd_is_leaf(KdNode node) { return (node.header & 3u) == MBAO_KD_LEAF; }
MBAO_FN mbao_u32 kd_axis(KdNode node) { return node.header & 3u; }
MBAO_FN float kd_split(KdNode node) { return mbao_u32_as_float(node.payload); }
MBAO_FN mbao_u32 kd_above_child(KdNode node) { return node.header >> 2; }
MBAO_FN mbao_u32 kd_triangle_count(KdNode node) { return node.header >> 2; }
MBAO_FN mbao_u32 kd_first_index(KdNode node) { return node.payload; }
MBAO_FN mbao_u32 kd_entry_triangle(mbao_u32 entry) { return entry & ~MBAO_KD_ENTRY_MASKED; }
MBAO_FN int kd_entry_masked(mbao_u32 entry) { return (entry & MBAO_KD_ENTRY_MASKED) != 0; }

#endif
