#pragma once

#include <cstdint>
#include <vector>

#include "accel/kd_tree.h"

namespace mbao {

// The kd-tree as the kernels read it (kernels/mbao/kd_node.h): KdTree's nodes
// in their order, depth first, with each non-empty leaf's triangle ids right
// after the leaf's node, two to a node's 8 bytes. A leaf's fetch then brings
// its first ids in the same cache line, where a separate list cost a walk a
// second dependent miss per leaf (docs/traversal-on-pocl.md). Interior nodes
// keep the child below right after them, and every index is remapped.
// Throws mbao::Error where the nodes and lists exceed what a node can address.
std::vector<KdNode> kd_device_layout(const KdTree& tree);

}  // namespace mbao
