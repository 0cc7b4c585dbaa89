// The kd-tree's contract with the traversal kernels: every leaf holds every
// triangle that touches its closed cell (and none whose box misses it), every
// split lies strictly inside its cell, and the node words decode to what was built.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <random>
#include <set>

#include "accel/kd_tree.h"
#include "mbao/alpha_mask.h"
#include "mbao/limits.h"
#include "random_soup.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

Bounds3 triangle_box(const TriangleMesh& mesh, std::size_t t) {
  Bounds3 box;
  for (int k = 0; k < 3; ++k) box.extend(mesh.positions[mesh.triangles[t][k]]);
  return box;
}

bool has_area(const TriangleMesh& mesh, std::size_t t) {
  const glm::dvec3 a = mesh.positions[mesh.triangles[t][0]];
  const glm::dvec3 n = glm::cross(glm::dvec3(mesh.positions[mesh.triangles[t][1]]) - a,
                                  glm::dvec3(mesh.positions[mesh.triangles[t][2]]) - a);
  return n != glm::dvec3(0.0);
}

bool touches(const Bounds3& a, const Bounds3& b) {
  for (int axis = 0; axis < 3; ++axis)
    if (a.hi[axis] < b.lo[axis] || a.lo[axis] > b.hi[axis]) return false;
  return true;
}

// Separating-axis test of a triangle against a closed box (Akenine-Moller
// 2001), in double: the box's 3 axes, the triangle's normal and the 9 cross
// products of their edges.
bool triangle_touches_box(const TriangleMesh& mesh, std::size_t t, const Bounds3& box) {
  const glm::dvec3 center = 0.5 * (glm::dvec3(box.lo) + glm::dvec3(box.hi));
  const glm::dvec3 half = 0.5 * (glm::dvec3(box.hi) - glm::dvec3(box.lo));
  glm::dvec3 v[3];
  for (int k = 0; k < 3; ++k) v[k] = glm::dvec3(mesh.positions[mesh.triangles[t][k]]) - center;
  const glm::dvec3 edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  std::vector<glm::dvec3> axes = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, glm::cross(edges[0], edges[1])};
  for (const glm::dvec3& e : edges)
    for (int a = 0; a < 3; ++a) axes.push_back(glm::cross(e, glm::dvec3(a == 0, a == 1, a == 2)));
  for (const glm::dvec3& axis : axes) {
    const double p0 = glm::dot(v[0], axis), p1 = glm::dot(v[1], axis), p2 = glm::dot(v[2], axis);
    const double radius = glm::dot(half, glm::abs(axis));
    if (std::min({p0, p1, p2}) > radius || std::max({p0, p1, p2}) < -radius) return false;
  }
  return true;
}

// The tree's nodes in order, without the leaves' lists.
std::vector<KdNode> tree_nodes(const KdTree& tree) {
  std::vector<KdNode> nodes;
  for (const std::uint32_t row : kd_node_rows(tree)) nodes.push_back(tree.nodes[row]);
  return nodes;
}

// The triangles a leaf lists.
std::vector<std::uint32_t> leaf_triangles(const KdTree& tree, KdNode leaf) {
  EXPECT_TRUE(kd_is_leaf(leaf));
  std::vector<std::uint32_t> triangles;
  for (std::uint32_t k = 0; k < kd_triangle_count(leaf); ++k)
    triangles.push_back(kd_entry_triangle(kd_leaf_entry(tree.nodes, leaf, k)));
  return triangles;
}

struct Walk {
  const TriangleMesh& mesh;
  const KdTree& tree;
  const KdBuildOptions options;
  const std::vector<std::uint32_t>& triangle_mask;
  double sah = 0.0;
  std::size_t nodes = 0, leaves = 0, empty_leaves = 0, references = 0;
  std::size_t slots = 0;  // nodes and their lists' nodes
  int depth = 0;

  void visit(std::uint32_t index, const Bounds3& cell, int level) {
    ASSERT_LT(index, tree.nodes.size());
    depth = std::max(depth, level);
    const KdNode node = tree.nodes[index];
    const double area = cell.surface_area() / tree.bounds.surface_area();
    ++nodes;
    slots += 1 + kd_list_nodes(node);
    if (kd_is_leaf(node)) {
      check_leaf(index, node, cell);
      ++leaves;
      empty_leaves += kd_triangle_count(node) == 0;
      sah += area * options.intersection_cost * kd_triangle_count(node);
      return;
    }
    sah += area * options.traversal_cost;
    const int axis = int(kd_axis(node));
    const float split = kd_split(node);
    ASSERT_GT(split, cell.lo[axis]) << "split on the cell's wall at node " << index;
    ASSERT_LT(split, cell.hi[axis]) << "split on the cell's wall at node " << index;
    Bounds3 below = cell, above = cell;
    below.hi[axis] = split;
    above.lo[axis] = split;
    visit(index + 1, below, level + 1);
    visit(kd_above_child(node), above, level + 1);
  }

  // The leaf's entries follow it, sorted, flagged where masked, and list
  // every triangle that touches its cell and none whose box misses it.
  void check_leaf(std::uint32_t index, KdNode node, const Bounds3& cell) {
    const std::uint32_t count = kd_triangle_count(node);
    ASSERT_EQ(kd_first_index(node), 2 * (index + 1)) << "leaf " << index << ": its entries follow it";
    ASSERT_LE(index + 1 + kd_list_nodes(node), tree.nodes.size());
    references += count;
    std::vector<std::uint32_t> listed;
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t entry = kd_leaf_entry(tree.nodes, node, k), t = kd_entry_triangle(entry);
      ASSERT_LT(t, mesh.triangles.size());
      ASSERT_EQ(kd_entry_masked(entry), t < triangle_mask.size() && triangle_mask[t] != MBAO_NOT_MASKED)
          << "triangle " << t;
      listed.push_back(t);
    }
    if (count % 2) {
      ASSERT_EQ(kd_leaf_entry(tree.nodes, node, count), 0u) << "the unused word of leaf " << index;
    }
    ASSERT_TRUE(std::is_sorted(listed.begin(), listed.end()));
    const std::set<std::uint32_t> in_leaf(listed.begin(), listed.end());
    ASSERT_EQ(in_leaf.size(), listed.size()) << "a triangle listed twice";
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      if (!has_area(mesh, t)) {
        ASSERT_FALSE(in_leaf.count(t)) << "zero-area triangle " << t << " in a leaf";
        continue;
      }
      if (triangle_touches_box(mesh, t, cell)) {
        ASSERT_TRUE(in_leaf.count(t)) << "triangle " << t << " touches the leaf cell but is not in the leaf";
      }
      if (!touches(triangle_box(mesh, t), cell)) {
        ASSERT_FALSE(in_leaf.count(t)) << "triangle " << t << " is in a leaf its box does not touch";
      }
    }
  }
};

// Checks the whole contract for `mesh` and returns the tree.
KdTree checked_tree(const TriangleMesh& mesh, const KdBuildOptions& options = {},
                    const std::vector<std::uint32_t>& triangle_mask = {}) {
  const KdTree tree = build_kd_tree(mesh, options, glm::vec3(0.0f), triangle_mask);
  EXPECT_EQ(tree.bounds.lo, mesh.bounds().lo);
  EXPECT_EQ(tree.bounds.hi, mesh.bounds().hi);
  Walk walk{mesh, tree, options, triangle_mask};
  walk.visit(0, tree.bounds, 0);
  // Every node and list node is reached once from the root: nothing is left over.
  EXPECT_EQ(walk.slots, tree.nodes.size());
  EXPECT_EQ(kd_node_rows(tree).size(), walk.nodes);
  EXPECT_EQ(tree.stats.memory_bytes, tree.nodes.size() * sizeof(KdNode));
  EXPECT_EQ(tree.stats.nodes, walk.nodes);
  EXPECT_EQ(tree.stats.leaves, walk.leaves);
  EXPECT_EQ(tree.stats.empty_leaves, walk.empty_leaves);
  EXPECT_EQ(tree.stats.max_depth, walk.depth);
  EXPECT_EQ(tree.stats.leaf_references, walk.references);
  EXPECT_EQ(walk.nodes, 2 * walk.leaves - 1);  // every interior node has two children
  if (tree.bounds.surface_area() > 0) {
    EXPECT_NEAR(tree.stats.sah_cost, walk.sah, 1e-9 * walk.sah);
  }
  return tree;
}

// Axis-aligned unit quads on an integer grid in all three orientations: many
// triangles share planes, edges and box faces.
TriangleMesh axis_aligned_grid(int n) {
  TriangleMesh mesh;
  for (int axis = 0; axis < 3; ++axis)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const auto base = std::uint32_t(mesh.positions.size());
        for (int corner = 0; corner < 4; ++corner) {
          glm::vec3 p(0.0f);
          p[axis] = float((i + j) % n);
          p[u] = float(i + (corner == 1 || corner == 2));
          p[v] = float(j + (corner >= 2));
          mesh.positions.push_back(p);
        }
        mesh.triangles.push_back({base, base + 1, base + 2});
        mesh.triangles.push_back({base, base + 2, base + 3});
      }
  return mesh;
}

// n random triangles in the square [0, 1]^2 of the plane z = 0: they overlap
// everywhere, and a split frees only the few whose edges it separates.
TriangleMesh overlapping_coplanar(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  TriangleMesh mesh;
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) mesh.positions.push_back({unit(rng), unit(rng), 0.0f});
    const auto base = std::uint32_t(3 * i);
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

// Small triangles along a spiral that shrinks toward its centre by `shrink` per
// triangle: every turn is a smaller copy of the last, which the SAH keeps cutting.
TriangleMesh shrinking_spiral(std::size_t n, float shrink) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> jitter(-0.5f, 0.5f);
  TriangleMesh mesh;
  for (std::size_t i = 0; i < n; ++i) {
    const float r = std::pow(shrink, float(i));
    const glm::vec3 center(r * std::cos(float(i)), r * std::sin(float(i)), r);
    for (int k = 0; k < 3; ++k)
      mesh.positions.push_back(center + 1e-3f * r * glm::vec3(jitter(rng), jitter(rng), jitter(rng)));
    const auto base = std::uint32_t(3 * i);
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

// A fan of n needles in a plane through the origin that no axis is parallel to:
// each runs from an apex `length` away to a 1 / n wide piece of a unit segment,
// so their aspect ratio is n * length.
TriangleMesh needle_fan(std::size_t n, float length) {
  const glm::vec3 normal = glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f));
  const glm::vec3 along = glm::normalize(glm::cross(normal, glm::vec3(1.0f, 0.0f, 0.0f)));
  const glm::vec3 across = glm::cross(normal, along);
  TriangleMesh mesh;
  mesh.positions.push_back(-length * along);
  for (std::size_t i = 0; i <= n; ++i) mesh.positions.push_back((float(i) / float(n) - 0.5f) * across);
  for (std::uint32_t i = 0; i < n; ++i) mesh.triangles.push_back({0, i + 1, i + 2});
  return mesh;
}

bool same_tree(const KdTree& a, const KdTree& b) {
  if (a.nodes.size() != b.nodes.size()) return false;
  for (std::size_t i = 0; i < a.nodes.size(); ++i)
    if (a.nodes[i].header != b.nodes[i].header || a.nodes[i].payload != b.nodes[i].payload) return false;
  return true;
}

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

// Clipping everywhere, nowhere, and (the default) only in the larger nodes.
std::vector<KdBuildOptions> clipping_variants() {
  KdBuildOptions everywhere, nowhere;
  everywhere.min_triangles_to_clip = 0;
  nowhere.min_triangles_to_clip = std::numeric_limits<std::size_t>::max();
  return {everywhere, nowhere, KdBuildOptions{}};
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
  // Subtrees' costs are summed in another order.
  EXPECT_NEAR(serial.stats.sah_cost, parallel.stats.sah_cost, 1e-12 * serial.stats.sah_cost);
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
