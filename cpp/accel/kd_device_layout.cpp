#include "accel/kd_device_layout.h"

#include <algorithm>
#include <string>

#include "core/error.h"
#include "mbao/alpha_mask.h"

namespace mbao {
namespace {

// Nodes a leaf's list takes after it: two entries to a node.
std::size_t list_slots(KdNode node) {
  return kd_is_leaf(node) ? (std::size_t(kd_triangle_count(node)) + 1) / 2 : 0;
}

std::uint32_t leaf_entry(std::uint32_t triangle, const std::vector<std::uint32_t>& triangle_mask) {
  if (triangle & MBAO_KD_ENTRY_MASKED)
    throw Error("kd-tree: triangle id " + std::to_string(triangle) + " needs the bit of a leaf entry's mask flag");
  const bool masked = triangle < triangle_mask.size() && triangle_mask[triangle] != MBAO_NOT_MASKED;
  return masked ? triangle | MBAO_KD_ENTRY_MASKED : triangle;
}

}  // namespace

std::size_t kd_device_layout_size(const KdTree& tree) {
  std::size_t slots = 0;
  for (const KdNode node : tree.nodes) slots += 1 + list_slots(node);
  // Leaves address their lists in 32-bit words, two per node.
  if (slots > MBAO_KD_MAX_INDEX)
    throw Error("kd-tree: " + std::to_string(slots) + " nodes with the leaves' lists inlined, more than the node " +
                "format can address (" + std::to_string(MBAO_KD_MAX_INDEX) + ")");
  return slots;
}

std::vector<KdNode> kd_device_layout(const KdTree& tree, const std::vector<std::uint32_t>& triangle_mask) {
  std::vector<KdNode> layout(kd_device_layout_size(tree));
  kd_device_layout_into(tree, triangle_mask, layout.data());
  return layout;
}

void kd_device_layout_into(const KdTree& tree, const std::vector<std::uint32_t>& triangle_mask, KdNode* layout) {
  // Each node's slot; 32 bits hold every index the format can address.
  std::vector<std::uint32_t> placed(tree.nodes.size());
  std::uint32_t slots = 0;
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    placed[i] = slots;
    slots += std::uint32_t(1 + list_slots(tree.nodes[i]));
  }
  std::fill(layout, layout + slots, KdNode{0, 0});
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const KdNode node = tree.nodes[i];
    const auto at = std::uint32_t(placed[i]);
    if (!kd_is_leaf(node)) {
      layout[at] = kd_make_interior(kd_axis(node), kd_split(node), std::uint32_t(placed[kd_above_child(node)]));
      continue;
    }
    const std::uint32_t count = kd_triangle_count(node);
    layout[at] = kd_make_leaf(count, 2 * (at + 1));
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t entry = leaf_entry(tree.leaf_triangles[kd_first_index(node) + k], triangle_mask);
      KdNode& pair = layout[at + 1 + k / 2];  // words 2 (at + 1) + k: header first
      (k % 2 ? pair.payload : pair.header) = entry;
    }
  }
}

}  // namespace mbao
