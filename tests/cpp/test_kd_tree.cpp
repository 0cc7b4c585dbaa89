// The kd-tree keeps its contract with the traversal kernels (kd_tree_contract.h)
// on every kind of mesh: random soups, shared planes, walls on the bounding box,
// flat scenes, clusters in empty space, inseparable and masked triangles.
#include <gtest/gtest.h>

#include "kd_tree_contract.h"
#include "random_soup.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

TEST(KdNode, WordsRoundTrip) {
  const KdNode interior = kd_make_interior(2, -3.25f, 123456);
  EXPECT_FALSE(kd_is_leaf(interior));
  EXPECT_EQ(kd_axis(interior), 2u);
  EXPECT_EQ(kd_split(interior), -3.25f);
  EXPECT_EQ(kd_above_child(interior), 123456u);
  const KdNode leaf = kd_make_leaf(MBAO_KD_MAX_INDEX, 0xFFFFFFFFu);
  EXPECT_TRUE(kd_is_leaf(leaf));
  EXPECT_EQ(kd_triangle_count(leaf), MBAO_KD_MAX_INDEX);
  EXPECT_EQ(kd_first_index(leaf), 0xFFFFFFFFu);
  EXPECT_EQ(sizeof(KdNode), 8u);
}

TEST(KdTree, RandomSoupsKeepTheLeafContract) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const TriangleMesh mesh = random_soup(2000, seed);
    const KdTree tree = checked_tree(mesh);
    EXPECT_GT(tree.stats.leaves, 100u);
    EXPECT_LT(tree.stats.sah_cost, KdBuildOptions{}.intersection_cost * double(mesh.triangles.size()) / 20.0);
  }
}

TEST(KdTree, CutBoxesKeepTheLeafContractWithOrWithoutClipping) {
  for (const KdBuildOptions& options : clipping_variants()) {
    checked_tree(random_soup(3000, 5), options);
    checked_tree(axis_aligned_grid(8), options);
  }
}

TEST(KdTree, PlanarTrianglesOnSharedPlanesKeepTheLeafContract) {
  const KdTree tree = checked_tree(axis_aligned_grid(8));
  EXPECT_GT(tree.stats.leaves, 10u);
}

TEST(KdTree, CornellWallsOnTheBoundingBoxAreCutIntoThinCells) {
  const auto scene = cornell_box();
  // Where triangle tests cost much more than steps, cutting a wall off pays.
  KdBuildOptions expensive_triangles;
  expensive_triangles.intersection_cost = 20.0;
  const KdTree tree = checked_tree(scene->mesh(), expensive_triangles);
  // The right wall (triangles 8 and 9) lies in the plane x = 0, a face of the
  // root cell. Some leaf holds it in a cell thinner than 1 mm along x.
  bool thin_leaf_with_wall = false;
  std::vector<std::pair<std::uint32_t, Bounds3>> stack = {{0u, tree.bounds}};
  while (!stack.empty()) {
    auto [index, cell] = stack.back();
    stack.pop_back();
    const KdNode node = tree.nodes[index];
    if (kd_is_leaf(node)) {
      const std::vector<std::uint32_t> listed = leaf_triangles(tree, node);
      if (cell.hi.x - cell.lo.x < 1.0f && std::count(listed.begin(), listed.end(), 8u)) thin_leaf_with_wall = true;
      continue;
    }
    Bounds3 below = cell, above = cell;
    below.hi[kd_axis(node)] = above.lo[kd_axis(node)] = kd_split(node);
    stack.push_back({index + 1, below});
    stack.push_back({kd_above_child(node), above});
  }
  EXPECT_TRUE(thin_leaf_with_wall);
}

TEST(KdTree, AFlatSceneIsNeverSplitAcrossItsPlane) {
  TriangleMesh mesh = axis_aligned_grid(6);
  TriangleMesh flat;
  for (const glm::uvec3& t : mesh.triangles) {  // keep the quads that lie in z = const, moved to z = 2
    const glm::vec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
    if (a.z != b.z || b.z != c.z) continue;
    const auto base = std::uint32_t(flat.positions.size());
    for (glm::vec3 p : {a, b, c}) flat.positions.push_back({p.x, p.y, 2.0f});
    flat.triangles.push_back({base, base + 1, base + 2});
  }
  const KdTree tree = checked_tree(flat);
  for (const KdNode& node : tree_nodes(tree)) {
    if (!kd_is_leaf(node)) {
      EXPECT_NE(kd_axis(node), 2u);
    }
  }
  EXPECT_GT(tree.stats.leaves, 1u);
}

TEST(KdTree, EmptySpaceAroundAClusterIsCutOff) {
  TriangleMesh mesh = random_soup(200, 7);
  for (glm::vec3& p : mesh.positions) p = 0.01f * p;  // a cluster in one corner of a big box
  const auto base = std::uint32_t(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {{10, 10, 10}, {10.1f, 10, 10}, {10, 10.1f, 10}});
  mesh.triangles.push_back({base, base + 1, base + 2});
  const KdTree tree = checked_tree(mesh);
  EXPECT_GT(tree.stats.empty_leaves, 0u);
}

TEST(KdTree, InseparableTrianglesEndInOneLeaf) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (int i = 0; i < 100; ++i) mesh.triangles.push_back({0, 1, 2});  // the same triangle 100 times
  const KdTree tree = checked_tree(mesh);
  EXPECT_EQ(tree.stats.max_depth, 0);
  EXPECT_EQ(tree.stats.leaf_references, 100u);
}

// The kernels look up the masks of flagged entries only (kernels/mbao/kd_node.h).
TEST(KdTree, EntriesOfMaskedTrianglesAreFlagged) {
  const TriangleMesh mesh = random_soup(2000, 7);
  std::vector<std::uint32_t> triangle_mask(mesh.triangles.size(), MBAO_NOT_MASKED);
  for (std::size_t t = 0; t < triangle_mask.size(); t += 3) triangle_mask[t] = std::uint32_t(t / 3);
  checked_tree(mesh, {}, triangle_mask);
}

TEST(KdTree, DepthStaysWithinTheLimit) {
  KdBuildOptions options;
  options.max_depth = 3;
  const KdTree tree = checked_tree(random_soup(5000, 11), options);
  EXPECT_LE(tree.stats.max_depth, 3);
}

}  // namespace
}  // namespace mbao
