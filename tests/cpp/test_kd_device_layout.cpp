// The kd-tree as the kernels read it: the same tree as KdTree's, node for node,
// with each leaf's entries (triangle ids, flagged where the triangle has an
// alpha mask) in the words right after the leaf.
#include <gtest/gtest.h>

#include "accel/kd_device_layout.h"
#include "core/error.h"
#include "mbao/alpha_mask.h"
#include "random_soup.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

std::uint32_t word(const std::vector<KdNode>& layout, std::size_t index) {
  const KdNode& pair = layout.at(index / 2);
  return index % 2 ? pair.payload : pair.header;
}

// Walks node `i` of the tree and node `at` of the layout together; returns the
// layout's nodes and list slots reached from them.
std::size_t expect_same_subtree(const KdTree& tree, std::size_t i, const std::vector<KdNode>& layout,
                                std::size_t at, const std::vector<std::uint32_t>& triangle_mask) {
  const KdNode node = tree.nodes.at(i), placed = layout.at(at);
  EXPECT_EQ(kd_is_leaf(placed), kd_is_leaf(node)) << "node " << i;
  if (!kd_is_leaf(node)) {
    EXPECT_EQ(kd_axis(placed), kd_axis(node));
    EXPECT_EQ(kd_split(placed), kd_split(node));
    // The child below stays right after its parent: the walks never store it.
    return 1 + expect_same_subtree(tree, i + 1, layout, at + 1, triangle_mask) +
           expect_same_subtree(tree, kd_above_child(node), layout, kd_above_child(placed), triangle_mask);
  }
  const std::uint32_t count = kd_triangle_count(node);
  EXPECT_EQ(kd_triangle_count(placed), count);
  EXPECT_EQ(kd_first_index(placed), 2 * (at + 1)) << "leaf " << i << ": its ids follow it";
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t entry = word(layout, kd_first_index(placed) + k);
    const std::uint32_t triangle = tree.leaf_triangles[kd_first_index(node) + k];
    EXPECT_EQ(kd_entry_triangle(entry), triangle);
    EXPECT_EQ(kd_entry_masked(entry), !triangle_mask.empty() && triangle_mask[triangle] != MBAO_NOT_MASKED);
  }
  return 1 + (count + 1) / 2;
}

void expect_layout_of(const KdTree& tree, const std::vector<std::uint32_t>& triangle_mask = {}) {
  const std::vector<KdNode> layout = kd_device_layout(tree, triangle_mask);
  // Every node and list slot is reached once from the root: nothing is left over.
  EXPECT_EQ(expect_same_subtree(tree, 0, layout, 0, triangle_mask), layout.size());
  std::size_t slots = tree.nodes.size();
  for (const KdNode& node : tree.nodes)
    if (kd_is_leaf(node)) slots += (kd_triangle_count(node) + 1) / 2;
  EXPECT_EQ(layout.size(), slots);
}

TEST(KdDeviceLayout, IsTheTreeWithEachLeafsIdsAfterIt) {
  expect_layout_of(build_kd_tree(random_soup(3000, 3)));
  expect_layout_of(build_kd_tree(cornell_box()->mesh()));
}

TEST(KdDeviceLayout, OddAndEmptyListsTakeWholeNodes) {
  // root: split at 0.5 on y; below: a leaf of 3 ids, above: an empty leaf.
  KdTree tree;
  tree.nodes = {kd_make_interior(1, 0.5f, 2), kd_make_leaf(3, 0), kd_make_leaf(0, 3)};
  tree.leaf_triangles = {7, 8, 9};
  const std::vector<KdNode> layout = kd_device_layout(tree);
  ASSERT_EQ(layout.size(), 5u);  // root, leaf, two nodes of ids (one word unused), empty leaf
  EXPECT_EQ(kd_above_child(layout[0]), 4u);
  expect_layout_of(tree);
}

TEST(KdDeviceLayout, EntriesOfMaskedTrianglesAreFlagged) {
  const TriangleMesh mesh = random_soup(2000, 7);
  std::vector<std::uint32_t> triangle_mask(mesh.triangles.size(), MBAO_NOT_MASKED);
  for (std::size_t t = 0; t < triangle_mask.size(); t += 3) triangle_mask[t] = std::uint32_t(t / 3);
  expect_layout_of(build_kd_tree(mesh), triangle_mask);
}

TEST(KdDeviceLayout, TooManyNodesForTheNodeFormatAreAnError) {
  // Two leaves of 2^30 - 1 ids each need 2^30 + 3 nodes with their lists; the
  // check comes before the lists are read, so they need not exist.
  KdTree tree;
  tree.nodes = {kd_make_interior(0, 0.5f, 2), kd_make_leaf(MBAO_KD_MAX_INDEX, 0),
                kd_make_leaf(MBAO_KD_MAX_INDEX, 0)};
  EXPECT_THROW(
      {
        try {
          kd_device_layout(tree);
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find("more than the node format can address"), std::string::npos)
              << e.what();
          throw;
        }
      },
      Error);
}

}  // namespace
}  // namespace mbao
