// SAH kd-tree construction after Wald and Havran, "On building fast kd-trees
// for ray tracing, and on doing that in O(N log N)" (2006): split events are
// sorted once per axis and then split, in order, between the children.
//
// In nodes of at least KdBuildOptions::min_triangles_to_clip triangles,
// straddling triangles are clipped to the children's cells ("perfect splits");
// below that their boxes are cut at the split plane.
// Two choices differ from the paper, both for exact traversal:
// * A triangle goes into every child whose closed cell it touches, so a ray
//   that lies in a split plane finds everything on that plane.
// * Split planes sit a small distance `min_width` off the event positions, and
//   no child is thinner than that. Every cell thus has a real width along each
//   axis it was split on: a ray cannot skip a cell because the distances to its
//   two walls round to the same float. A planar triangle on the node boundary
//   (the Cornell box walls) is cut off into a cell of that width.
//
// A third choice bounds memory: each subtree gets a budget of leaf entries, the
// root `reference_budget` per triangle, and a node is split only if its children
// fit into its budget, which they then share in proportion to their triangle
// counts; the whole tree thus holds at most that many entries per triangle.
// Without it, thousands of overlapping coplanar triangles (decals, z-fighting
// copies) drive the build to its depth limit: each split frees a few triangles
// from the other side, which the SAH finds worth it, while nearly all of them
// go to both children, and the entries double with each level (4000 such
// triangles took 7 minutes and 1.3 GB).
//
// Subtrees big enough to pay for a hand-over are offered to idle threads
// (core/work_sharing.h); one that another thread takes is built into arrays of
// its own and appended in depth-first order, so the tree does not depend on
// the number of threads.
#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <future>
#include <glm/geometric.hpp>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "accel/event_partition.h"
#include "accel/kd_tree.h"
#include "accel/sah_sweep.h"
#include "accel/split_events.h"
#include "core/error.h"
#include "core/timer.h"
#include "core/work_sharing.h"
#include "mbao/alpha_mask.h"
#include "mbao/limits.h"

namespace mbao {
namespace {

// Below this many triangles a subtree is built by the thread that split its
// parent: handing it over would cost more than the subtree takes.
constexpr std::size_t kMinTrianglesToOffer = 2048;

// Rows (nodes and leaves' lists) reserved per triangle before a tree or a
// subtree is built: trees of the shared scenes and of generated spheres take
// 4.4-5. Growing the array instead copies it and touches twice its pages;
// room reserved and never written is never touched, so it takes no memory.
constexpr std::size_t kRowsReservedPerTriangle = 6;

// What a thread needs while it builds a node, reused from node to node.
struct Scratch {
  explicit Scratch(std::size_t triangles) : partition(triangles) {}

  PartitionScratch partition;
  std::vector<std::uint32_t> leaf_entries;  // of a leaf, before they are sorted
  std::size_t rows_not_counted = 0;         // written since the last Builder::count_rows
  SweepBlocks sweep;
};

// A node's triangles and the leaf entries its subtree may hold.
struct Share {
  std::size_t triangles = 0;
  double budget = 0.0;
};

// A node still to be built, with what building it needs.
struct Subtree {
  Bounds3 box;
  NodeEvents events;
  Share share;
  int depth = 0;
};

// Appends a subtree built in an array of its own: its child indices move by
// the size of what is already there, and its leaves' lists, which follow them,
// by twice that in words. (Indices past the format's range wrap here; build()
// then throws.)
void append_subtree(KdTree& tree, const KdTree& part) {
  const auto offset = std::uint32_t(tree.nodes.size());
  for (std::size_t i = 0; i < part.nodes.size(); ++i) {
    const KdNode node = part.nodes[i];
    if (!kd_is_leaf(node)) {
      tree.nodes.push_back(kd_make_interior(kd_axis(node), kd_split(node), kd_above_child(node) + offset));
      continue;
    }
    tree.nodes.push_back(kd_make_leaf(kd_triangle_count(node), kd_first_index(node) + 2 * offset));
    const std::size_t list = kd_list_nodes(node);
    tree.nodes.insert(tree.nodes.end(), part.nodes.begin() + std::ptrdiff_t(i + 1),
                      part.nodes.begin() + std::ptrdiff_t(i + 1 + list));
    i += list;
  }
  tree.stats.nodes += part.stats.nodes;
  tree.stats.leaves += part.stats.leaves;
  tree.stats.empty_leaves += part.stats.empty_leaves;
  tree.stats.leaf_references += part.stats.leaf_references;
  tree.stats.max_depth = std::max(tree.stats.max_depth, part.stats.max_depth);
  tree.stats.sah_cost += part.stats.sah_cost;
}

// Runs f(0), f(1), f(2), on three threads when `parallel`.
template <class AxisFunction>
void for_each_axis(bool parallel, const AxisFunction& f) {
  if (!parallel) {
    for (int axis = 0; axis < 3; ++axis) f(axis);
    return;
  }
  auto y = std::async(std::launch::async, f, 1);
  auto z = std::async(std::launch::async, f, 2);
  f(0);
  y.get();
  z.get();
}

// Runs f(first, last) on `parts` ranges that cover [0, count) in order, the
// first on this thread and each other one on a thread of its own.
template <class RangeFunction>
void for_each_range(std::size_t count, int parts, const RangeFunction& f) {
  const auto bound = [&](int part) { return count * std::size_t(part) / std::size_t(parts); };
  std::vector<std::future<void>> others;
  for (int part = 1; part < parts; ++part)
    others.push_back(std::async(std::launch::async, f, bound(part), bound(part + 1)));
  f(bound(0), bound(1));
  for (std::future<void>& other : others) other.get();
}

class Builder {
 public:
  Builder(const TriangleMesh& mesh, const KdBuildOptions& options, const glm::vec3& origin,
          const std::vector<std::uint32_t>& triangle_mask)
      : mesh_{mesh.positions, mesh.triangles, origin},
        triangle_mask_(triangle_mask),
        options_(options),
        threads_(options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()))) {}

  KdTree build() {
    Stopwatch clock;
    KdTree tree;
    for (std::uint32_t v = 0; v < mesh_.positions.size(); ++v) tree.bounds.extend(mesh_.position(v));
    const std::size_t n = mesh_.triangles.size();
    if (n > std::size_t(kMaxEventTriangle) + 1) throw Error("kd-tree: more than 2^30 triangles");
    max_depth_ = options_.max_depth > 0 ? options_.max_depth
                                        : int(std::lround(8.0 + 1.3 * std::log2(double(std::max<std::size_t>(n, 1)))));
    max_depth_ = std::min(max_depth_, MBAO_KD_MAX_DEPTH);  // the full-stack traversal's stack depth
    const glm::vec3 extent = tree.bounds.extent();
    const float largest = std::max({extent.x, extent.y, extent.z});
    const glm::vec3 far_corner = glm::max(glm::abs(tree.bounds.lo), glm::abs(tree.bounds.hi));
    const float magnitude = std::max({far_corner.x, far_corner.y, far_corner.z});
    // 2^-17 of the scene, and never less than a few float steps of its coordinates.
    min_width_ = std::max(largest * 0x1p-17f, magnitude * 8.0f * std::numeric_limits<float>::epsilon());
    root_area_ = tree.bounds.surface_area();

    std::size_t placed = 0;
    NodeEvents events = root_events(tree.bounds, placed);
    tree.stats.degenerate_triangles = n - placed;
    Scratch scratch(n);
    reserve_rows(tree, n);
    if (threads_ > 1) {
      sharing_ = std::make_unique<SubtreeSharing>(
          threads_ - 1, [n] { return Scratch(n); },
          [this](Subtree& subtree, Scratch& helper_scratch) { return build_apart(subtree, helper_scratch); });
    }
    build_node(tree, scratch, tree.bounds, std::move(events), {placed, options_.reference_budget * double(placed)}, 0);
    sharing_.reset();

    // Leaves address their lists in 32-bit words, two per node.
    if (tree.nodes.size() > MBAO_KD_MAX_INDEX)
      throw Error("kd-tree: " + std::to_string(tree.nodes.size()) + " nodes with the leaves' lists, more than the " +
                  "node format can address (" + std::to_string(MBAO_KD_MAX_INDEX) + ")");
    const std::size_t filled = tree.stats.leaves - tree.stats.empty_leaves;
    tree.stats.mean_triangles_per_leaf = filled ? double(tree.stats.leaf_references) / double(filled) : 0.0;
    tree.stats.memory_bytes = tree.nodes.size() * sizeof(KdNode);
    tree.stats.build_ms = clock.elapsed_ms();
    return tree;
  }

 private:
  // Exact for float input: the differences and products of floats are exact
  // in double, so only a triangle whose corners are collinear gets a zero
  // cross product. No ray can hit such a triangle, so it stays out of the tree.
  bool has_zero_area(std::uint32_t t) const {
    const std::array<glm::vec3, 3> p = mesh_.corners(t);
    const glm::dvec3 n = glm::cross(glm::dvec3(p[1]) - glm::dvec3(p[0]), glm::dvec3(p[2]) - glm::dvec3(p[0]));
    return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
  }

  // The triangles of non-zero area, in order.
  std::vector<std::uint32_t> triangles_with_area(bool parallel) const {
    const std::size_t n = mesh_.triangles.size();
    std::unique_ptr<bool[]> has_area(new bool[n]);
    for_each_range(n, parallel ? threads_ : 1, [&](std::size_t first, std::size_t last) {
      for (std::size_t t = first; t < last; ++t) has_area[t] = !has_zero_area(std::uint32_t(t));
    });
    std::vector<std::uint32_t> kept;
    kept.reserve(n);
    for (std::uint32_t t = 0; t < n; ++t)
      if (has_area[t]) kept.push_back(t);
    return kept;
  }

  // The root's events: those of every triangle of non-zero area, sorted, each
  // axis's on a thread of its own. They are made from the corners as they are
  // sorted (make_sorted_events), with no boxes kept: those took 24 bytes a
  // triangle at the build's peak.
  NodeEvents root_events(const Bounds3& bounds, std::size_t& placed) const {
    const bool parallel = threads_ > 1 && mesh_.triangles.size() >= kMinTrianglesToOffer;  // else threads cost more
    const std::vector<std::uint32_t> kept = triangles_with_area(parallel);
    placed = kept.size();
    NodeEvents events(2 * kept.size());
    for_each_axis(parallel, [&](int axis) {
      const auto make = [&](auto&& push) {
        for (const std::uint32_t t : kept) {
          const std::array<glm::vec3, 3> p = mesh_.corners(t);
          const float lo = std::min({p[0][axis], p[1][axis], p[2][axis]});
          const float hi = std::max({p[0][axis], p[1][axis], p[2][axis]});
          for_interval_events(lo, hi, t, push);
        }
      };
      events.close_axis(axis, make_sorted_events(make, bounds.lo[axis], bounds.hi[axis], events.begin(axis)));
    });
    return events;
  }

  double area_fraction(const Bounds3& box) const { return root_area_ > 0.0 ? box.surface_area() / root_area_ : 0.0; }

  void build_node(KdTree& tree, Scratch& scratch, const Bounds3& box, NodeEvents events, Share share, int depth) {
    tree.stats.max_depth = std::max(tree.stats.max_depth, depth);
    const std::size_t n = share.triangles;
    const Split split =
        n > 0 && depth < max_depth_ ? find_split(box, events, n, options_, min_width_, scratch.sweep) : Split{};
    if (split.axis < 0 || split.cost >= options_.intersection_cost * double(n)) {
      make_leaf(tree, scratch, box, events);
      return;
    }
    Bounds3 below_box = box, above_box = box;
    below_box.hi[split.axis] = split.position;
    above_box.lo[split.axis] = split.position;
    // A plane below or above all of the node's events (one that cuts off
    // empty space: 39% of Sponza's splits) leaves every triangle on one side
    // as it is, so the child on that side takes the node's events as they
    // are, with no pass over them; it gets them once the budget allows.
    const bool empty_below = split.sweep_index < 0;
    const bool one_sided = empty_below || split.sweep_index == std::ptrdiff_t(events.size(split.axis));
    Children children;
    if (one_sided) {
      (empty_below ? children.n_above : children.n_below) = n;
    } else {
      children = n >= options_.min_triangles_to_clip
                     ? partition_clipping(events, split, below_box, above_box, mesh_, scratch.partition)
                     : partition_cutting_boxes(events, split, scratch.partition);
    }
    const double entries = double(children.n_below) + double(children.n_above);
    if (entries > share.budget) {
      make_leaf(tree, scratch, box, events);
      return;
    }
    if (one_sided) {
      (empty_below ? children.above : children.below) = std::move(events);
    } else {
      fill_children(events, scratch.partition, children);
    }
    events = NodeEvents{};  // release the parent's events before going deeper

    tree.stats.sah_cost += area_fraction(box) * options_.traversal_cost;
    ++tree.stats.nodes;
    const std::size_t index = tree.nodes.size();
    tree.nodes.push_back(kd_make_interior(std::uint32_t(split.axis), split.position, 0));
    count_rows(scratch, 1);
    const Share below{children.n_below, share.budget * double(children.n_below) / entries};
    const Share above{children.n_above, share.budget * double(children.n_above) / entries};
    Subtree above_part{above_box, std::move(children.above), above, depth + 1};
    const SubtreeSharing::OfferHandle offer =
        sharing_ && above.triangles >= kMinTrianglesToOffer ? sharing_->offer(std::move(above_part)) : nullptr;
    build_node(tree, scratch, below_box, std::move(children.below), below, depth + 1);
    tree.nodes[index] = kd_make_interior(std::uint32_t(split.axis), split.position, std::uint32_t(tree.nodes.size()));
    if (offer) {
      std::optional<Subtree> taken_back = sharing_->take_back(offer);
      if (!taken_back) {
        append_subtree(tree, sharing_->wait_for(offer, scratch));
        return;
      }
      above_part = std::move(*taken_back);
    }
    if (above.triangles < kMinTrianglesToOffer) {
      build_node(tree, scratch, above_part.box, std::move(above_part.events), above_part.share, above_part.depth);
      return;
    }
    // A subtree that could have been offered has its cost summed on its own,
    // as a helper thread sums it, so the total does not depend on who built it.
    const double before = std::exchange(tree.stats.sah_cost, 0.0);
    build_node(tree, scratch, above_part.box, std::move(above_part.events), above_part.share, above_part.depth);
    tree.stats.sah_cost += before;
  }

  void reserve_rows(KdTree& tree, std::size_t triangles) const {
    tree.nodes.reserve(std::min(kRowsReservedPerTriangle * triangles, options_.max_bytes / sizeof(KdNode)));
  }

  // A subtree that another thread took, in arrays of its own.
  KdTree build_apart(Subtree& subtree, Scratch& scratch) {
    KdTree part;
    reserve_rows(part, subtree.share.triangles);
    build_node(part, scratch, subtree.box, std::move(subtree.events), subtree.share, subtree.depth);
    return part;
  }

  // The leaf's node, then its entries two to a node (the last one's second
  // word 0 where they are odd), ordered by triangle and flagged where the
  // triangle has an alpha mask.
  void make_leaf(KdTree& tree, Scratch& scratch, const Bounds3& box, const NodeEvents& events) {
    std::vector<std::uint32_t>& entries = scratch.leaf_entries;
    entries.clear();
    for (const Event *e = events.begin(0), *end = events.end(0); e != end; ++e)
      if (begins_triangle(e->type())) entries.push_back(e->triangle());
    std::sort(entries.begin(), entries.end());
    const std::size_t count = entries.size();
    if (count > MBAO_KD_MAX_INDEX) throw Error("kd-tree: leaf too large for the node format");
    const auto at = std::uint32_t(tree.nodes.size());  // build() throws where the nodes outgrow 32-bit words
    tree.nodes.push_back(kd_make_leaf(std::uint32_t(count), 2 * (at + 1)));
    for (std::size_t k = 0; k < count; k += 2)
      tree.nodes.push_back({leaf_entry(entries[k]), k + 1 < count ? leaf_entry(entries[k + 1]) : 0u});
    count_rows(scratch, 1 + (count + 1) / 2);
    ++tree.stats.nodes;
    ++tree.stats.leaves;
    tree.stats.empty_leaves += count == 0;
    tree.stats.leaf_references += count;
    tree.stats.sah_cost += area_fraction(box) * options_.intersection_cost * double(count);
  }

  // Adds rows written by this thread to the count of all threads, in batches
  // of 32 KiB of nodes, so that the threads rarely touch the shared count,
  // and stops the build where their bytes pass options_.max_bytes.
  void count_rows(Scratch& scratch, std::size_t rows) {
    constexpr std::size_t kRowsPerBatch = 4096;
    scratch.rows_not_counted += rows;
    if (scratch.rows_not_counted < kRowsPerBatch) return;
    const std::size_t total = rows_written_.fetch_add(scratch.rows_not_counted) + scratch.rows_not_counted;
    scratch.rows_not_counted = 0;
    if (total > options_.max_bytes / sizeof(KdNode)) throw KdTreeTooLarge(total * sizeof(KdNode), options_.max_bytes);
  }

  std::uint32_t leaf_entry(std::uint32_t triangle) const {
    const bool masked = triangle < triangle_mask_.size() && triangle_mask_[triangle] != MBAO_NOT_MASKED;
    return masked ? triangle | MBAO_KD_ENTRY_MASKED : triangle;
  }

  const TreeFrameMesh mesh_;
  const std::vector<std::uint32_t>& triangle_mask_;
  const KdBuildOptions& options_;
  const int threads_;
  int max_depth_ = 0;
  float min_width_ = 0.0f;
  double root_area_ = 0.0;
  std::atomic<std::size_t> rows_written_{0};  // by all threads, but for those not counted yet
  using SubtreeSharing = WorkSharing<Subtree, Scratch, KdTree>;
  // With more than one thread. Last, so that its helpers stop before the
  // rest of the builder goes.
  std::unique_ptr<SubtreeSharing> sharing_;
};

}  // namespace

KdTree build_kd_tree(const TriangleMesh& mesh, const KdBuildOptions& options, const glm::vec3& origin,
                     const std::vector<std::uint32_t>& triangle_mask) {
  return Builder(mesh, options, origin, triangle_mask).build();
}

}  // namespace mbao
