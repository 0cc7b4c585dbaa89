#pragma once

#include <cstdint>
#include <vector>

#include "accel/kd_tree.h"

namespace mbao {

// The kd-tree as the kernels read it (kernels/mbao/kd_node.h): KdTree's nodes
// in their order, depth first, with each non-empty leaf's entries right after
// the leaf's node, two to a node's 8 bytes. A leaf's fetch then brings its
// first entries in the same cache line, where a separate list cost a walk a
// second dependent miss per leaf (docs/traversal.md). Interior nodes
// keep the child below right after them, and every index is remapped.
//
// An entry is a triangle id with MBAO_KD_ENTRY_MASKED set where
// triangle_mask (AlphaMasks::triangle_mask; empty: no masks) gives the
// triangle one. Throws mbao::Error where the nodes and lists exceed what a
// node can address, or an id needs the flag's bit.
std::vector<KdNode> kd_device_layout(const KdTree& tree, const std::vector<std::uint32_t>& triangle_mask = {});

// The layout's length in nodes; throws as kd_device_layout does.
std::size_t kd_device_layout_size(const KdTree& tree);
// The layout written into `layout`, kd_device_layout_size(tree) nodes: into a
// mapped device buffer, with no copy of it in host memory.
void kd_device_layout_into(const KdTree& tree, const std::vector<std::uint32_t>& triangle_mask, KdNode* layout);

}  // namespace mbao
