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
// Subtrees big enough to pay for a thread are built on spare threads into
// arrays of their own and appended in depth-first order, so the tree does not
// depend on the number of threads.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <future>
#include <glm/geometric.hpp>
#include <limits>
#include <memory>
#include <thread>

#include "accel/kd_tree.h"
#include "accel/split_events.h"
#include "accel/triangle_clip.h"
#include "core/error.h"
#include "core/timer.h"
#include "mbao/limits.h"

namespace mbao {
namespace {

// Below this many triangles a subtree is built by the thread that split its
// parent: starting a thread would cost more than the subtree takes.
constexpr std::size_t kMinTrianglesPerThread = 2048;

enum Side : std::uint8_t { Below, Above, Both };

struct Split {
  int axis = -1;
  float position = 0.0f;
  double cost = std::numeric_limits<double>::infinity();
};

// Exact for float input: the differences and products of floats are exact in
// double, so only a triangle whose corners are collinear gets a zero cross product.
// No ray can hit such a triangle, so it stays out of the tree.
bool has_zero_area(const TriangleMesh& mesh, std::uint32_t t) {
  const glm::dvec3 p0 = mesh.positions[mesh.triangles[t][0]];
  const glm::dvec3 e1 = glm::dvec3(mesh.positions[mesh.triangles[t][1]]) - p0;
  const glm::dvec3 e2 = glm::dvec3(mesh.positions[mesh.triangles[t][2]]) - p0;
  const glm::dvec3 n = glm::cross(e1, e2);
  return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
}

// What a thread needs while it splits a node, reused from node to node.
struct Scratch {
  // Written for every triangle of a node before it is read: no need to clear.
  explicit Scratch(std::size_t triangles) : side(new Side[triangles]) {}

  std::unique_ptr<Side[]> side;  // by triangle index
  // New events of straddling triangles, by axis, before they are merged in.
  std::array<std::vector<Event>, 3> clipped_below, clipped_above;

  void clear_new_events() {
    for (int axis = 0; axis < 3; ++axis) {
      clipped_below[axis].clear();
      clipped_above[axis].clear();
    }
  }
};

struct Children {
  NodeEvents below, above;
  std::size_t n_below = 0, n_above = 0;
};

// A node's triangles and the leaf entries its subtree may hold.
struct Share {
  std::size_t triangles = 0;
  double budget = 0.0;
};

// Appends a subtree built in arrays of its own: its child and leaf-list
// indices move by the sizes of what is already there. (Indices past the
// format's range wrap here; build() then throws.)
void append_subtree(KdTree& tree, const KdTree& part) {
  const auto node_offset = std::uint32_t(tree.nodes.size());
  const auto leaf_offset = std::uint32_t(tree.leaf_triangles.size());
  tree.nodes.reserve(tree.nodes.size() + part.nodes.size());
  for (const KdNode node : part.nodes)
    tree.nodes.push_back(kd_is_leaf(node)
                             ? kd_make_leaf(kd_triangle_count(node), kd_first_index(node) + leaf_offset)
                             : kd_make_interior(kd_axis(node), kd_split(node), kd_above_child(node) + node_offset));
  tree.leaf_triangles.insert(tree.leaf_triangles.end(), part.leaf_triangles.begin(), part.leaf_triangles.end());
  tree.stats.leaves += part.stats.leaves;
  tree.stats.empty_leaves += part.stats.empty_leaves;
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

class Builder {
 public:
  Builder(const TriangleMesh& mesh, const KdBuildOptions& options)
      : mesh_(mesh),
        options_(options),
        threads_(options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()))),
        spare_threads_(threads_ - 1) {}

  KdTree build() {
    Stopwatch clock;
    KdTree tree;
    tree.bounds = mesh_.bounds();
    const std::size_t n = mesh_.triangles.size();
    if (n > std::size_t(kMaxEventTriangle) + 1) throw Error("kd-tree: more than 2^30 triangles");
    max_depth_ = options_.max_depth > 0
                     ? options_.max_depth
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
    NodeEvents events = root_events(placed);
    tree.stats.degenerate_triangles = n - placed;
    Scratch scratch(n);
    build_node(tree, scratch, tree.bounds, std::move(events), {placed, options_.reference_budget * double(placed)}, 0);

    if (tree.nodes.size() > MBAO_KD_MAX_INDEX) throw Error("kd-tree: more nodes than the node format can address");
    if (tree.leaf_triangles.size() > std::numeric_limits<std::uint32_t>::max())
      throw Error("kd-tree: more leaf entries than the node format can address");
    tree.stats.nodes = tree.nodes.size();
    tree.stats.leaf_references = tree.leaf_triangles.size();
    const std::size_t filled = tree.stats.leaves - tree.stats.empty_leaves;
    tree.stats.mean_triangles_per_leaf = filled ? double(tree.leaf_triangles.size()) / double(filled) : 0.0;
    tree.stats.memory_bytes = tree.nodes.size() * sizeof(KdNode) + tree.leaf_triangles.size() * sizeof(std::uint32_t);
    tree.stats.build_ms = clock.elapsed_ms();
    return tree;
  }

 private:
  Bounds3 triangle_box(std::uint32_t t) const {
    Bounds3 box;
    for (int k = 0; k < 3; ++k) box.extend(mesh_.positions[mesh_.triangles[t][k]]);
    return box;
  }

  std::array<glm::vec3, 3> corners(std::uint32_t t) const {
    const glm::uvec3& v = mesh_.triangles[t];
    return {mesh_.positions[v[0]], mesh_.positions[v[1]], mesh_.positions[v[2]]};
  }

  // Every triangle of non-zero area, its events made in triangle order and
  // sorted (one axis per thread).
  NodeEvents root_events(std::size_t& placed) const {
    std::vector<std::uint32_t> kept;
    std::vector<Bounds3> boxes;
    for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (has_zero_area(mesh_, t)) continue;
      kept.push_back(t);
      boxes.push_back(triangle_box(t));
    }
    placed = kept.size();
    NodeEvents events(6 * kept.size());
    for (int axis = 0; axis < 3; ++axis) {
      for (std::size_t i = 0; i < kept.size(); ++i) events.push_box(axis, boxes[i], kept[i]);
      events.close_axis(axis);
    }
    for_each_axis(threads_ > 1,
                  [&events](int axis) { sort_events_made_by_triangle(events.begin(axis), events.end(axis)); });
    return events;
  }

  double area_fraction(const Bounds3& box) const { return root_area_ > 0.0 ? box.surface_area() / root_area_ : 0.0; }

  void build_node(KdTree& tree, Scratch& scratch, const Bounds3& box, NodeEvents events, Share share, int depth) {
    tree.stats.max_depth = std::max(tree.stats.max_depth, depth);
    const std::size_t n = share.triangles;
    const Split split = n > 0 && depth < max_depth_ ? find_split(box, events, n) : Split{};
    if (split.axis < 0 || split.cost >= options_.intersection_cost * double(n)) {
      make_leaf(tree, box, events);
      return;
    }
    Bounds3 below_box = box, above_box = box;
    below_box.hi[split.axis] = split.position;
    above_box.lo[split.axis] = split.position;
    Children children = n >= options_.min_triangles_to_clip ? partition(events, split, below_box, above_box, scratch)
                                                             : partition_cutting_boxes(events, split, scratch);
    const double entries = double(children.n_below) + double(children.n_above);
    if (entries > share.budget) {
      make_leaf(tree, box, events);
      return;
    }
    events = NodeEvents{};  // release the parent's events before going deeper

    tree.stats.sah_cost += area_fraction(box) * options_.traversal_cost;
    const std::size_t index = tree.nodes.size();
    tree.nodes.push_back(kd_make_interior(std::uint32_t(split.axis), split.position, 0));
    const Share below{children.n_below, share.budget * double(children.n_below) / entries};
    const Share above{children.n_above, share.budget * double(children.n_above) / entries};
    std::future<KdTree> above_part = build_on_spare_thread(above_box, children.above, above, depth + 1);
    build_node(tree, scratch, below_box, std::move(children.below), below, depth + 1);
    tree.nodes[index] = kd_make_interior(std::uint32_t(split.axis), split.position, std::uint32_t(tree.nodes.size()));
    if (above_part.valid()) {
      append_subtree(tree, above_part.get());
    } else {
      build_node(tree, scratch, above_box, std::move(children.above), above, depth + 1);
    }
  }

  // A subtree on a thread of its own, when one is spare and the subtree is
  // big enough to pay for it; else an empty future and `events` untouched.
  std::future<KdTree> build_on_spare_thread(const Bounds3& box, NodeEvents& events, Share share, int depth) {
    if (share.triangles < kMinTrianglesPerThread || !take_spare_thread()) return {};
    return std::async(std::launch::async, [this, box, events = std::move(events), share, depth]() mutable {
      struct GiveBack {
        std::atomic<int>& spare;
        ~GiveBack() { spare.fetch_add(1); }
      } give_back{spare_threads_};
      KdTree part;
      Scratch scratch(mesh_.triangles.size());
      build_node(part, scratch, box, std::move(events), share, depth);
      return part;
    });
  }

  bool take_spare_thread() {
    int spare = spare_threads_.load();
    while (spare > 0 && !spare_threads_.compare_exchange_weak(spare, spare - 1)) {
    }
    return spare > 0;
  }

  // Sweeps each axis's sorted events. Between two event positions p < q the
  // planes p + min_width (what ends at p goes below) and q - min_width (what
  // starts at q goes above) are candidates, with the same counts on either
  // side; below the first position and above the last one, the planes that
  // cut off empty space. The partition itself is exact. Costs are compared
  // times the node's half area, which saves a division per candidate.
  Split find_split(const Bounds3& box, const NodeEvents& events, std::size_t n) const {
    Split best;
    const glm::dvec3 extent = glm::dvec3(box.hi) - glm::dvec3(box.lo);
    const double half_area = extent.x * extent.y + extent.y * extent.z + extent.z * extent.x;
    if (!(half_area > 0.0)) return best;
    const double traversal = options_.traversal_cost * half_area, intersection = options_.intersection_cost;
    const double empty_factor = 1.0 - options_.empty_bonus;
    for (int axis = 0; axis < 3; ++axis) {
      const float lo = box.lo[axis], hi = box.hi[axis];
      if (hi - lo < 2.0f * min_width_) continue;
      // A child's half area is cap + (its width along axis) * girth.
      const double cap = extent[(axis + 1) % 3] * extent[(axis + 2) % 3];
      const double girth = extent[(axis + 1) % 3] + extent[(axis + 2) % 3];
      const auto fits = [&](float position) { return position - lo >= min_width_ && hi - position >= min_width_; };
      const auto consider = [&](float position, std::size_t n_below, std::size_t n_above) {
        const double area_below = cap + (double(position) - double(lo)) * girth;
        const double area_above = cap + (double(hi) - double(position)) * girth;
        const double lambda = (n_below == 0 || n_above == 0) ? empty_factor : 1.0;
        const double cost =
            lambda * (traversal + intersection * (area_below * double(n_below) + area_above * double(n_above)));
        if (cost < best.cost) best = {axis, position, cost};
      };
      // Between two positions the cost is linear in the plane's position,
      // rising where more triangles lie below than above: only the cheaper
      // end is priced (the lower one on a tie, as the sweep meets it first),
      // or the other one where the cheaper does not fit.
      const auto consider_gap = [&](float left, float right, std::size_t n_below, std::size_t n_above) {
        const bool rising = n_below > n_above;
        const bool take_left = n_below == n_above || rising == (left <= right);
        const float cheaper = take_left ? left : right, dearer = take_left ? right : left;
        if (fits(cheaper)) {
          consider(cheaper, n_below, n_above);
        } else if (fits(dearer)) {
          consider(dearer, n_below, n_above);
        }
      };
      std::size_t starts_before = 0, ends_before = 0;
      const Event *e = events.begin(axis), *end = events.end(axis);
      if (e == end) continue;
      if (fits(e->position() - min_width_)) consider(e->position() - min_width_, 0, n);
      float previous = 0.0f;  // the last position swept
      while (e != end) {
        const std::uint32_t at = e->position_order();
        const float p = e->position();
        if (e != events.begin(axis))
          consider_gap(previous + min_width_, p - min_width_, starts_before, n - ends_before);
        std::array<std::size_t, 3> count{};  // by EventType
        for (; e != end && e->position_order() == at; ++e) ++count[std::size_t(e->type())];
        const std::size_t planar = count[std::size_t(EventType::Planar)];
        starts_before += count[std::size_t(EventType::Start)] + planar;
        ends_before += count[std::size_t(EventType::End)] + planar;
        previous = p;
      }
      if (fits(previous + min_width_)) consider(previous + min_width_, n, 0);
    }
    best.cost /= half_area;
    return best;
  }

  // Splits the events between the children, keeping their order. A triangle
  // on both sides is clipped to each child: where it misses a child's cell it
  // stays out of it, elsewhere it gets new events for its clipped box, sorted
  // and merged in.
  Children partition(const NodeEvents& events, const Split& split, const Bounds3& below_box,
                     const Bounds3& above_box, Scratch& scratch) const {
    Side* side = scratch.side.get();
    classify(events, split, side);
    scratch.clear_new_events();
    Children children;
    for (const Event *e = events.begin(split.axis), *end = events.end(split.axis); e != end; ++e) {
      if (e->type() == EventType::End) continue;
      const std::uint32_t t = e->triangle();
      if (side[t] == Below) {
        ++children.n_below;
      } else if (side[t] == Above) {
        ++children.n_above;
      } else {
        const auto [below_part, above_part] = clipped_bounds_of_split(corners(t), below_box, above_box, split.axis);
        children.n_below += add_events(t, below_part, scratch.clipped_below);
        children.n_above += add_events(t, above_part, scratch.clipped_above);
      }
    }
    fill_children(events, side, -1, scratch, children);
    return children;
  }

  // Which side of the split each triangle of the node is on, from one pass
  // over the split axis's events in order: a start below the split makes a
  // triangle straddle until its end, if that is below too, makes it Below.
  static void classify(const NodeEvents& events, const Split& split, Side* side) {
    for (const Event *e = events.begin(split.axis), *end = events.end(split.axis); e != end; ++e) {
      const std::uint32_t t = e->triangle();
      const EventType type = e->type();
      const float position = e->position();
      if (position < split.position) {
        side[t] = type == EventType::Start ? Both : Below;
      } else if (type != EventType::End) {
        side[t] = position > split.position ? Above : Both;
      }
    }
  }

  // Like partition, but a straddling triangle's box is cut at the split: its
  // interval [s, e] along the split axis becomes [s, split] below and
  // [split, e] above (planar where that is one point), and its events along
  // the other axes go to both children as they are.
  Children partition_cutting_boxes(const NodeEvents& events, const Split& split, Scratch& scratch) const {
    Side* side = scratch.side.get();
    classify(events, split, side);
    scratch.clear_new_events();
    std::vector<Event>& below = scratch.clipped_below[std::size_t(split.axis)];
    std::vector<Event>& above = scratch.clipped_above[std::size_t(split.axis)];
    Children children;
    for (const Event *e = events.begin(split.axis), *end = events.end(split.axis); e != end; ++e) {
      const std::uint32_t t = e->triangle();
      const EventType type = e->type();
      if (side[t] != Both) {
        (side[t] == Below ? children.n_below : children.n_above) += type != EventType::End;
      } else if (type == EventType::Planar) {  // on the split plane
        below.push_back(*e);
        above.push_back(*e);
        ++children.n_below;
        ++children.n_above;
      } else if (type == EventType::Start) {  // s <= split
        ++children.n_below;
        ++children.n_above;
        if (e->position() < split.position) {
          below.push_back(*e);
          below.push_back(Event::make(split.position, EventType::End, t));
        } else {
          below.push_back(Event::make(split.position, EventType::Planar, t));
        }
      } else if (e->position() > split.position) {  // e > split
        above.push_back(Event::make(split.position, EventType::Start, t));
        above.push_back(*e);
      } else {  // e == split
        above.push_back(Event::make(split.position, EventType::Planar, t));
      }
    }
    fill_children(events, side, split.axis, scratch, children);
    return children;
  }

  // Adds the events of `box`, the part of triangle t in a child's cell, if
  // there is one; returns whether there was.
  static bool add_events(std::uint32_t t, const std::optional<Bounds3>& box, std::array<std::vector<Event>, 3>& out) {
    if (!box) return false;
    for (std::size_t axis = 0; axis < 3; ++axis)
      for_box_events(int(axis), *box, t, [&](const Event& e) { out[axis].push_back(e); });
    return true;
  }

  // Allocates the children's events and merges them in, axis by axis.
  // `cut_axis`: the split axis where straddlers' boxes were cut (their events
  // along the other axes then go to both children), or -1 where they were clipped.
  static void fill_children(const NodeEvents& events, const Side* side, int cut_axis, Scratch& scratch,
                            Children& children) {
    children.below = NodeEvents(6 * children.n_below);
    children.above = NodeEvents(6 * children.n_above);
    for (int axis = 0; axis < 3; ++axis)
      merge_sides(events, axis, side, scratch.clipped_below[std::size_t(axis)],
                  scratch.clipped_above[std::size_t(axis)], children, cut_axis >= 0 && axis != cut_axis);
  }

  // The children's events along `axis`: the parent's events of triangles
  // wholly on one side go to that side (and with `both_to_both`, those of
  // triangles on both sides to both), merged with the clipped triangles' new
  // events. One pass over the parent's events fills both children.
  static void merge_sides(const NodeEvents& parent, int axis, const Side* side, std::vector<Event>& clipped_below,
                          std::vector<Event>& clipped_above, Children& children, bool both_to_both) {
    // A sentinel above every event ends each run of new events without a bounds check.
    for (std::vector<Event>* clipped : {&clipped_below, &clipped_above}) {
      std::sort(clipped->begin(), clipped->end());
      clipped->push_back(Event::after_all());
    }
    const Event *extra_below = clipped_below.data(), *extra_above = clipped_above.data();
    Event* below = children.below.next_slot();
    Event* above = children.above.next_slot();
    // The side an event goes to is a coin flip to the branch predictor: each
    // event is written to both children and kept where it belongs.
    const std::array<std::uint8_t, 3> keep_below{1, 0, both_to_both}, keep_above{0, 1, both_to_both};  // by Side
    for (const Event *e = parent.begin(axis), *end = parent.end(axis); e != end; ++e) {
      const Event event = *e;
      while (*extra_below < event) *below++ = *extra_below++;
      while (*extra_above < event) *above++ = *extra_above++;
      const Side s = side[event.triangle()];
      *below = event;
      below += keep_below[s];
      *above = event;
      above += keep_above[s];
    }
    below = std::copy(extra_below, static_cast<const Event*>(&clipped_below.back()), below);
    above = std::copy(extra_above, static_cast<const Event*>(&clipped_above.back()), above);
    children.below.close_axis(axis, below);
    children.above.close_axis(axis, above);
  }

  void make_leaf(KdTree& tree, const Bounds3& box, const NodeEvents& events) const {
    const std::size_t first = tree.leaf_triangles.size();
    for (const Event *e = events.begin(0), *end = events.end(0); e != end; ++e)
      if (e->type() != EventType::End) tree.leaf_triangles.push_back(e->triangle());
    std::sort(tree.leaf_triangles.begin() + std::ptrdiff_t(first), tree.leaf_triangles.end());
    const std::size_t count = tree.leaf_triangles.size() - first;
    if (count > MBAO_KD_MAX_INDEX) throw Error("kd-tree: leaf too large for the node format");
    tree.nodes.push_back(kd_make_leaf(std::uint32_t(count), std::uint32_t(first)));
    ++tree.stats.leaves;
    tree.stats.empty_leaves += count == 0;
    tree.stats.sah_cost += area_fraction(box) * options_.intersection_cost * double(count);
  }

  const TriangleMesh& mesh_;
  const KdBuildOptions& options_;
  const int threads_;
  std::atomic<int> spare_threads_;
  int max_depth_ = 0;
  float min_width_ = 0.0f;
  double root_area_ = 0.0;
};

}  // namespace

KdTree build_kd_tree(const TriangleMesh& mesh, const KdBuildOptions& options) {
  return Builder(mesh, options).build();
}

}  // namespace mbao
