#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "mbao/kd_node.h"
#include "scene/bounds.h"
#include "scene/triangle_mesh.h"

namespace mbao {

// The surface area heuristic's constants (Wald and Havran 2006, section 3),
// chosen by the traversal counts and frame times of the shared scenes with the
// stack traversal: a node costs more than a triangle test there (the nodes'
// fetches miss the cache), so leaves stay fairly large.
struct KdBuildOptions {
  double traversal_cost = 1.0;     // K_T: one traversal step
  double intersection_cost = 0.5;  // K_I: one ray/triangle test
  double empty_bonus = 0.2;        // cost discount of a split that cuts off empty space
  int max_depth = 0;               // 0: 8 + 1.3 log2(N), as pbrt; at most MBAO_KD_MAX_DEPTH
  double reference_budget = 32.0;  // leaf entries per triangle the tree may hold, at most
  // Nodes with at least this many triangles clip straddling triangles to the
  // children's cells ("perfect splits"); smaller ones cut a straddler's box at
  // the plane. Near the leaves clipping costs a fifth of the build and buys
  // little: with 16, Sponza's tree builds in 0.8-0.9 of the time of
  // clipping everywhere, and the benchmark's AO rays visit 0.7% fewer nodes and
  // test 5% more triangles (docs/kd-tree-build.md).
  std::size_t min_triangles_to_clip = 16;
  // The most bytes the tree may take (a device's largest buffer): the build
  // stops with KdTreeTooLarge soon after its nodes pass it, not at its end.
  std::size_t max_bytes = std::numeric_limits<std::size_t>::max();
  int threads = 0;  // 0: one per hardware thread; the tree is the same for any number
  // Skip the SAH sweep's planes that a bound shows cannot be the cheapest
  // (longest axis first, then blocks of events by bound). The tree is the
  // same either way (a test checks); off, every plane is priced, as the
  // kd-build benchmark does to show what the pruning saves.
  bool prune_sweep = true;
};

struct KdTreeStats {
  std::size_t nodes = 0;  // interior nodes and leaves, not counting the leaves' lists
  std::size_t leaves = 0;
  std::size_t empty_leaves = 0;
  int max_depth = 0;
  double mean_triangles_per_leaf = 0.0;  // over non-empty leaves
  std::size_t leaf_references = 0;       // entries in the leaves' lists
  std::size_t degenerate_triangles = 0;  // zero-area triangles, left out: no ray can hit them
  double sah_cost = 0.0;                 // expected cost of a random ray, in K units
  double build_ms = 0.0;
  std::size_t memory_bytes = 0;  // nodes and the leaves' lists
};

// A kd-tree in the layout the kernels read (kernels/mbao/kd_node.h), on the
// host as on the device, so that a device that shares host memory reads
// these very nodes: depth first, each interior node's "below" child right
// after it, and each leaf's entries right after the leaf, two to a node's 8
// bytes. A leaf's fetch then brings its first entries in the same cache line,
// where a separate list cost a walk a second dependent miss per leaf
// (docs/traversal.md). An entry is a triangle id, with MBAO_KD_ENTRY_MASKED
// set where the triangle has an alpha mask.
//
// Every leaf lists every triangle of non-zero area that touches its closed
// cell (and none whose box misses the cell), so a point on a cell boundary is
// found from either side.
struct KdTree {
  std::vector<KdNode> nodes;  // the tree's nodes and the leaves' entries
  Bounds3 bounds;
  KdTreeStats stats;
};

// The nodes a leaf's entries take after it.
inline std::size_t kd_list_nodes(KdNode node) {
  return kd_is_leaf(node) ? (std::size_t(kd_triangle_count(node)) + 1) / 2 : 0;
}

// The indices of the tree's nodes in `tree.nodes`, depth first: every row but
// the leaves' lists.
inline std::vector<std::uint32_t> kd_node_rows(const KdTree& tree) {
  std::vector<std::uint32_t> rows;
  rows.reserve(tree.stats.nodes);
  for (std::size_t i = 0; i < tree.nodes.size(); i += 1 + kd_list_nodes(tree.nodes[i]))
    rows.push_back(std::uint32_t(i));
  return rows;
}

// Entry k of `leaf`'s list in `nodes`: its payload counts 32-bit words from the start.
inline std::uint32_t kd_leaf_entry(const std::vector<KdNode>& nodes, KdNode leaf, std::uint32_t k) {
  const std::size_t word = std::size_t(kd_first_index(leaf)) + k;
  const KdNode& pair = nodes[word / 2];
  return word % 2 ? pair.payload : pair.header;
}

// A build that stopped where its nodes passed KdBuildOptions::max_bytes.
class KdTreeTooLarge : public Error {
 public:
  KdTreeTooLarge(std::size_t bytes_written, std::size_t max_bytes)
      : Error("kd-tree: its nodes passed " + std::to_string(bytes_written) + " bytes, more than the " +
              std::to_string(max_bytes) + " allowed; the build stopped there"),
        bytes_written(bytes_written) {}
  std::size_t bytes_written;  // by then: past the limit by at most a batch of rows per thread and a leaf
};

// Builds the tree in O(N log N) with sorted split events (Wald and Havran 2006),
// subtrees in parallel. The tree's frame is the mesh's moved by -origin: its
// bounds and planes are those of the positions less `origin`, in float.
// triangle_mask (AlphaMasks::triangle_mask; empty: no masks) flags the entries
// of masked triangles.
KdTree build_kd_tree(const TriangleMesh& mesh, const KdBuildOptions& options = {},
                     const glm::vec3& origin = glm::vec3(0.0f), const std::vector<std::uint32_t>& triangle_mask = {});

}  // namespace mbao
