// What the kd-tree build guarantees beyond the leaf contract: the same tree
// whatever the sweep's pruning and the number of threads, and bounded work on
// pathological input (its byte limit, the reference budget, the depth limit,
// degenerate triangles).
#include <gtest/gtest.h>

#include "kd_tree_contract.h"
#include "random_soup.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

// The pruned sweep skips planes only where a bound shows they cost more
// than the best found; ties go as the full sweep meets them (axis 0 first,
// then along the axis), so the tree is the same. The grid's planes tie often.
TEST(KdTree, PruningTheSweepKeepsTheTree) {
  std::vector<TriangleMesh> meshes = {random_soup(3000, 31),        random_soup(500, 32),
                                      axis_aligned_grid(8),         overlapping_coplanar(400, 33),
                                      shrinking_spiral(300, 0.99f), cornell_box()->mesh()};
  TriangleMesh slab = random_soup(3000, 34);  // long cells: whole axes are skipped
  for (glm::vec3& p : slab.positions) p *= glm::vec3(40.0f, 1.0f, 0.2f);
  meshes.push_back(slab);
  std::vector<KdBuildOptions> variants = clipping_variants();
  KdBuildOptions expensive_triangles, no_empty_bonus;
  expensive_triangles.intersection_cost = 20.0;
  no_empty_bonus.empty_bonus = 0.0;
  variants.insert(variants.end(), {expensive_triangles, no_empty_bonus});
  for (std::size_t m = 0; m < meshes.size(); ++m)
    for (std::size_t v = 0; v < variants.size(); ++v) {
      KdBuildOptions pruned = variants[v], full = variants[v];
      pruned.prune_sweep = true;
      full.prune_sweep = false;
      const KdTree tree = build_kd_tree(meshes[m], pruned);
      EXPECT_GT(tree.stats.leaves, 1u) << "mesh " << m;
      EXPECT_TRUE(same_tree(tree, build_kd_tree(meshes[m], full))) << "mesh " << m << ", options " << v;
    }
}

TEST(KdTree, TheTreeDoesNotDependOnTheNumberOfThreads) {
  // Big enough for subtrees on spare threads (2048 triangles and more), with
  // triangles of no area spread over the parts in which threads make the
  // root's boxes.
  TriangleMesh mesh = random_soup(30000, 21);
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 997) mesh.triangles[t][2] = mesh.triangles[t][1];
  KdBuildOptions one_thread, four_threads;
  one_thread.threads = 1;
  four_threads.threads = 4;
  const KdTree serial = build_kd_tree(mesh, one_thread);
  const KdTree parallel = build_kd_tree(mesh, four_threads);
  ASSERT_EQ(serial.nodes.size(), parallel.nodes.size());
  for (std::size_t i = 0; i < serial.nodes.size(); ++i) {
    ASSERT_EQ(serial.nodes[i].header, parallel.nodes[i].header) << "node " << i;
    ASSERT_EQ(serial.nodes[i].payload, parallel.nodes[i].payload) << "node " << i;
  }
  EXPECT_EQ(serial.stats.max_depth, parallel.stats.max_depth);
  EXPECT_EQ(serial.stats.leaves, parallel.stats.leaves);
  EXPECT_GE(serial.stats.degenerate_triangles, 31u);
  EXPECT_EQ(serial.stats.degenerate_triangles, parallel.stats.degenerate_triangles);
  // Each subtree that a helper could take has its cost summed on its own, whoever builds it.
  EXPECT_EQ(serial.stats.sah_cost, parallel.stats.sah_cost);
}

// A device's largest buffer bounds the tree: the build stops once its
// threads' nodes pass it, long before the whole tree is there.
TEST(KdTree, ABuildThatPassesItsByteLimitStopsSoonAfter) {
  const TriangleMesh mesh = random_soup(40000, 23);
  const std::size_t whole = build_kd_tree(mesh).stats.memory_bytes;
  KdBuildOptions limited;
  limited.max_bytes = whole / 8;
  limited.threads = 4;
  try {
    build_kd_tree(mesh, limited);
    FAIL() << "no error";
  } catch (const KdTreeTooLarge& e) {
    EXPECT_GT(e.bytes_written, limited.max_bytes);
    EXPECT_LT(e.bytes_written, whole / 2) << "whole tree: " << whole << " bytes";
    EXPECT_NE(std::string(e.what()).find(std::to_string(limited.max_bytes) + " allowed"), std::string::npos);
  }
  limited.max_bytes = whole;
  EXPECT_EQ(build_kd_tree(mesh, limited).stats.memory_bytes, whole);
}

TEST(KdTree, SingleTriangleAndDegenerateTriangles) {
  TriangleMesh one;
  one.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}};
  one.triangles = {{0, 1, 2}};
  checked_tree(one);
  TriangleMesh degenerate = random_soup(300, 5);
  const auto base = std::uint32_t(degenerate.positions.size());
  degenerate.positions.insert(degenerate.positions.end(), {{0.5f, 0.5f, 0.5f}, {0.7f, 0.7f, 0.7f}, {0.9f, 0.9f, 0.9f}});
  degenerate.triangles.push_back({base, base + 1, base + 2});  // collinear
  degenerate.triangles.push_back({base, base, base});          // a point
  const KdTree tree = checked_tree(degenerate);
  std::size_t without_area = 0;
  for (std::size_t t = 0; t < degenerate.triangles.size(); ++t) without_area += !has_area(degenerate, t);
  EXPECT_GE(without_area, 2u);
  EXPECT_EQ(tree.stats.degenerate_triangles, without_area);
}

TEST(KdTree, OverlappingCoplanarTrianglesStayWithinTheReferenceBudget) {
  // Without the budget 2000 of these take a minute and 48 million leaf entries.
  const TriangleMesh mesh = overlapping_coplanar(2000, 9);
  const KdTree tree = checked_tree(mesh);
  EXPECT_LE(tree.stats.leaf_references, std::size_t(KdBuildOptions{}.reference_budget * 2000.0));
  EXPECT_GT(tree.stats.leaves, 1u);  // still split where that pays
  KdBuildOptions tight;
  tight.reference_budget = 3.0;
  EXPECT_LE(checked_tree(mesh, tight).stats.leaf_references, 6000u);
}

TEST(KdTree, TheReferenceBudgetLeavesOrdinaryTreesAlone) {
  KdBuildOptions unlimited;
  unlimited.reference_budget = std::numeric_limits<double>::infinity();
  const auto cornell = cornell_box();
  for (const TriangleMesh& mesh : {random_soup(3000, 4), axis_aligned_grid(8), cornell->mesh()})
    EXPECT_TRUE(same_tree(build_kd_tree(mesh), build_kd_tree(mesh, unlimited)));
}

TEST(KdTree, ThousandsOfIdenticalTrianglesShareOneLeaf) {
  TriangleMesh mesh = random_soup(500, 13);
  const auto base = std::uint32_t(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {{0.2f, 0.2f, 0.2f}, {0.6f, 0.3f, 0.2f}, {0.3f, 0.7f, 0.4f}});
  const std::uint32_t first_copy = std::uint32_t(mesh.triangles.size());
  for (int i = 0; i < 5000; ++i) mesh.triangles.push_back({base, base + 1, base + 2});
  const KdTree tree = checked_tree(mesh);  // every leaf its triangle touches lists all 5000 copies
  std::size_t copies = 0;
  for (const KdNode& node : tree_nodes(tree))
    if (kd_is_leaf(node))
      for (const std::uint32_t t : leaf_triangles(tree, node)) copies += t >= first_copy;
  EXPECT_EQ(copies % 5000, 0u);
  EXPECT_GE(copies, 5000u);
}

TEST(KdTree, TheDepthLimitHolds) {
  // The spiral would go 24 levels deep; a limit of 12 stops it there.
  const TriangleMesh mesh = shrinking_spiral(300, 0.97f);
  EXPECT_GT(build_kd_tree(mesh).stats.max_depth, 12);
  KdBuildOptions shallow;
  shallow.max_depth = 12;
  EXPECT_EQ(checked_tree(mesh, shallow).stats.max_depth, 12);
  // Beyond the full-stack traversal's stack it is that stack's depth.
  KdBuildOptions deepest, beyond;
  deepest.max_depth = MBAO_KD_MAX_DEPTH;
  beyond.max_depth = 1000;
  const KdTree tree = checked_tree(mesh, beyond);
  EXPECT_LE(tree.stats.max_depth, MBAO_KD_MAX_DEPTH);
  EXPECT_TRUE(same_tree(tree, build_kd_tree(mesh, deepest)));
}

TEST(KdTree, NeedlesAndSliversKeepTheLeafContract) {
  TriangleMesh mesh = needle_fan(1000, 1000.0f);  // aspect ratio 10^6
  // Slivers: three nearly collinear corners, the middle one 10^-6 off the line.
  for (int i = 0; i < 100; ++i) {
    const auto base = std::uint32_t(mesh.positions.size());
    const glm::vec3 start(-0.5f, float(i) * 0.01f - 0.5f, 0.3f);
    mesh.positions.insert(mesh.positions.end(),
                          {start, start + glm::vec3(1.0f, 0.5f, 0.2f), start + glm::vec3(0.5f, 0.25f + 1e-6f, 0.1f)});
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  const KdTree tree = checked_tree(mesh);
  EXPECT_EQ(tree.stats.degenerate_triangles, 0u);
  EXPECT_GT(tree.stats.leaves, 10u);
}

TEST(KdTree, OnlyDegenerateTrianglesGiveOneEmptyLeaf) {
  TriangleMesh mesh;
  mesh.positions = {{1, 2, 3}, {2, 3, 4}, {3, 4, 5}, {-1, 0, 7}};
  mesh.triangles = {{0, 1, 2}, {0, 0, 3}, {3, 3, 3}, {2, 1, 0}};  // collinear, repeated vertices, a point
  const KdTree tree = checked_tree(mesh);
  EXPECT_EQ(tree.nodes.size(), 1u);
  EXPECT_EQ(tree.stats.empty_leaves, 1u);
  EXPECT_EQ(tree.stats.degenerate_triangles, 4u);
  EXPECT_TRUE(std::isfinite(tree.stats.sah_cost));
  EXPECT_EQ(tree.bounds.lo, glm::vec3(-1, 0, 3));
  EXPECT_EQ(tree.bounds.hi, glm::vec3(3, 4, 7));
}

}  // namespace
}  // namespace mbao
