// The kd-tree's contract with the traversal kernels, checked node by node
// (test_kd_tree.cpp, test_kd_tree_build.cpp): every leaf holds every triangle
// that touches its closed cell (and none whose box misses it), every split lies
// strictly inside its cell, and the node words decode to what was built; and
// the meshes that test it hardest.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include "accel/kd_tree.h"
#include "mbao/alpha_mask.h"
#include "mbao/limits.h"

namespace mbao {

inline Bounds3 triangle_box(const TriangleMesh& mesh, std::size_t t) {
  Bounds3 box;
  for (int k = 0; k < 3; ++k) box.extend(mesh.positions[mesh.triangles[t][k]]);
  return box;
}

inline bool has_area(const TriangleMesh& mesh, std::size_t t) {
  const glm::dvec3 a = mesh.positions[mesh.triangles[t][0]];
  const glm::dvec3 n = glm::cross(glm::dvec3(mesh.positions[mesh.triangles[t][1]]) - a,
                                  glm::dvec3(mesh.positions[mesh.triangles[t][2]]) - a);
  return n != glm::dvec3(0.0);
}

inline bool touches(const Bounds3& a, const Bounds3& b) {
  for (int axis = 0; axis < 3; ++axis)
    if (a.hi[axis] < b.lo[axis] || a.lo[axis] > b.hi[axis]) return false;
  return true;
}

// Separating-axis test of a triangle against a closed box (Akenine-Moller
// 2001), in double: the box's 3 axes, the triangle's normal and the 9 cross
// products of their edges.
inline bool triangle_touches_box(const TriangleMesh& mesh, std::size_t t, const Bounds3& box) {
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
inline std::vector<KdNode> tree_nodes(const KdTree& tree) {
  std::vector<KdNode> nodes;
  for (const std::uint32_t row : kd_node_rows(tree)) nodes.push_back(tree.nodes[row]);
  return nodes;
}

// The triangles a leaf lists.
inline std::vector<std::uint32_t> leaf_triangles(const KdTree& tree, KdNode leaf) {
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
inline KdTree checked_tree(const TriangleMesh& mesh, const KdBuildOptions& options = {},
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

// Clipping everywhere, nowhere, and (the default) only in the larger nodes.
inline std::vector<KdBuildOptions> clipping_variants() {
  KdBuildOptions everywhere, nowhere;
  everywhere.min_triangles_to_clip = 0;
  nowhere.min_triangles_to_clip = std::numeric_limits<std::size_t>::max();
  return {everywhere, nowhere, KdBuildOptions{}};
}

// Axis-aligned unit quads on an integer grid in all three orientations: many
// triangles share planes, edges and box faces.
inline TriangleMesh axis_aligned_grid(int n) {
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
inline TriangleMesh overlapping_coplanar(std::size_t n, unsigned seed) {
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
inline TriangleMesh shrinking_spiral(std::size_t n, float shrink) {
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
inline TriangleMesh needle_fan(std::size_t n, float length) {
  const glm::vec3 normal = glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f));
  const glm::vec3 along = glm::normalize(glm::cross(normal, glm::vec3(1.0f, 0.0f, 0.0f)));
  const glm::vec3 across = glm::cross(normal, along);
  TriangleMesh mesh;
  mesh.positions.push_back(-length * along);
  for (std::size_t i = 0; i <= n; ++i) mesh.positions.push_back((float(i) / float(n) - 0.5f) * across);
  for (std::uint32_t i = 0; i < n; ++i) mesh.triangles.push_back({0, i + 1, i + 2});
  return mesh;
}

inline bool same_tree(const KdTree& a, const KdTree& b) {
  if (a.nodes.size() != b.nodes.size()) return false;
  for (std::size_t i = 0; i < a.nodes.size(); ++i)
    if (a.nodes[i].header != b.nodes[i].header || a.nodes[i].payload != b.nodes[i].payload) return false;
  return true;
}

}  // namespace mbao
