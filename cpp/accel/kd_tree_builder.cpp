// SAH kd-tree construction after Wald and Havran, "On building fast kd-trees
// for ray tracing, and on doing that in O(N log N)" (2006): split events are
// sorted once per axis and then split, in order, between the children.
//
// Straddling triangles are clipped to the children's cells ("perfect splits").
// Two choices differ from the paper, both for exact traversal:
// * A triangle goes into every child whose closed cell it touches, so a ray
//   that lies in a split plane finds everything on that plane.
// * Split planes sit a small distance `min_width` off the event positions, and
//   no child is thinner than that. Every cell thus has a real width along each
//   axis it was split on: a ray cannot skip a cell because the distances to its
//   two walls round to the same float. A planar triangle on the node boundary
//   (the Cornell box walls) is cut off into a cell of that width.
#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

#include "accel/kd_tree.h"
#include "accel/triangle_clip.h"
#include "mbao/limits.h"
#include "core/error.h"
#include "core/timer.h"

namespace mbao {
namespace {

enum class EventType : std::uint8_t { End, Planar, Start };

struct Event {
  float position;
  std::uint32_t triangle;
  EventType type;
};

bool operator<(const Event& a, const Event& b) {
  return a.position < b.position || (a.position == b.position && a.type < b.type);
}

using EventLists = std::array<std::vector<Event>, 3>;

enum Side : std::uint8_t { Left, Right, Both };

struct Split {
  int axis = -1;
  float position = 0.0f;
  double cost = std::numeric_limits<double>::infinity();
};

void append_events(const Bounds3& box, std::uint32_t triangle, EventLists& events) {
  for (int axis = 0; axis < 3; ++axis) {
    if (box.lo[axis] == box.hi[axis]) {
      events[axis].push_back({box.lo[axis], triangle, EventType::Planar});
    } else {
      events[axis].push_back({box.lo[axis], triangle, EventType::Start});
      events[axis].push_back({box.hi[axis], triangle, EventType::End});
    }
  }
}

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

class Builder {
 public:
  Builder(const TriangleMesh& mesh, const KdBuildOptions& options)
      : mesh_(mesh),
        options_(options),
        side_(mesh.triangles.size()),
        extent_lo_(mesh.triangles.size()),
        extent_hi_(mesh.triangles.size()) {
    triangle_boxes_.reserve(mesh.triangles.size());
    for (const glm::uvec3& t : mesh.triangles) {
      Bounds3 box;
      for (int k = 0; k < 3; ++k) box.extend(mesh.positions[t[k]]);
      triangle_boxes_.push_back(box);
    }
  }

  KdTree build() {
    Stopwatch clock;
    KdTree tree;
    tree.bounds = mesh_.bounds();
    const std::size_t n = mesh_.triangles.size();
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

    EventLists events;
    std::size_t placed = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (has_zero_area(mesh_, i)) continue;
      append_events(triangle_boxes_[i], i, events);
      ++placed;
    }
    tree.stats.degenerate_triangles = n - placed;
    for (auto& list : events) std::sort(list.begin(), list.end());
    build_node(tree, tree.bounds, std::move(events), placed, 0);

    tree.stats.nodes = tree.nodes.size();
    tree.stats.leaf_references = tree.leaf_triangles.size();
    const std::size_t filled = tree.stats.leaves - tree.stats.empty_leaves;
    tree.stats.mean_triangles_per_leaf = filled ? double(tree.leaf_triangles.size()) / double(filled) : 0.0;
    tree.stats.memory_bytes = tree.nodes.size() * sizeof(KdNode) + tree.leaf_triangles.size() * sizeof(std::uint32_t);
    tree.stats.build_ms = clock.elapsed_ms();
    return tree;
  }

 private:
  double area_fraction(const Bounds3& box) const { return root_area_ > 0.0 ? box.surface_area() / root_area_ : 0.0; }

  double split_cost(const Bounds3& box, int axis, float position, std::size_t n_left, std::size_t n_right) const {
    Bounds3 left = box, right = box;
    left.hi[axis] = position;
    right.lo[axis] = position;
    const double area = box.surface_area();
    const double p_left = left.surface_area() / area, p_right = right.surface_area() / area;
    const double lambda = (n_left == 0 || n_right == 0) ? 1.0 - options_.empty_bonus : 1.0;
    return lambda * (options_.traversal_cost +
                     options_.intersection_cost * (p_left * double(n_left) + p_right * double(n_right)));
  }

  // Sweeps each axis's sorted events. At an event position p two planes are
  // tried: p - min_width (what starts at p goes right) and p + min_width
  // (what ends at p goes left). The counts treat them as just below and just
  // above p; the partition itself is exact.
  Split find_split(const Bounds3& box, const EventLists& events, std::size_t n) const {
    Split best;
    for (int axis = 0; axis < 3; ++axis) {
      const float lo = box.lo[axis], hi = box.hi[axis];
      if (hi - lo < 2.0f * min_width_) continue;
      const std::vector<Event>& list = events[axis];
      std::size_t starts_before = 0, ends_before = 0;
      for (std::size_t i = 0; i < list.size();) {
        const float p = list[i].position;
        std::size_t ending = 0, planar = 0, starting = 0;
        for (; i < list.size() && list[i].position == p; ++i) {
          ending += list[i].type == EventType::End;
          planar += list[i].type == EventType::Planar;
          starting += list[i].type == EventType::Start;
        }
        consider(box, axis, p - min_width_, starts_before, n - ends_before, best);
        starts_before += starting + planar;
        ends_before += ending + planar;
        consider(box, axis, p + min_width_, starts_before, n - ends_before, best);
      }
    }
    return best;
  }

  void consider(const Bounds3& box, int axis, float position, std::size_t n_left, std::size_t n_right,
                Split& best) const {
    if (!(position - box.lo[axis] >= min_width_ && box.hi[axis] - position >= min_width_)) return;
    const double cost = split_cost(box, axis, position, n_left, n_right);
    if (cost < best.cost) best = {axis, position, cost};
  }

  std::uint32_t build_node(KdTree& tree, const Bounds3& box, EventLists events, std::size_t n, int depth) {
    tree.stats.max_depth = std::max(tree.stats.max_depth, depth);
    const std::uint32_t index = std::uint32_t(tree.nodes.size());
    const Split split = n > 0 && depth < max_depth_ ? find_split(box, events, n) : Split{};
    if (split.axis < 0 || split.cost >= options_.intersection_cost * double(n)) {
      make_leaf(tree, box, events[0]);
      return index;
    }
    tree.stats.sah_cost += area_fraction(box) * options_.traversal_cost;
    tree.nodes.push_back(kd_make_interior(std::uint32_t(split.axis), split.position, 0));

    Bounds3 left_box = box, right_box = box;
    left_box.hi[split.axis] = split.position;
    right_box.lo[split.axis] = split.position;
    EventLists left, right;
    std::size_t n_left = 0, n_right = 0;
    partition(events, split, left_box, right_box, left, right, n_left, n_right);
    events = EventLists{};  // release the parent's lists before going deeper

    build_node(tree, left_box, std::move(left), n_left, depth + 1);
    const std::uint32_t above = std::uint32_t(tree.nodes.size());
    if (above > MBAO_KD_MAX_INDEX) throw Error("kd-tree: more nodes than the node format can address");
    tree.nodes[index] = kd_make_interior(std::uint32_t(split.axis), split.position, above);
    build_node(tree, right_box, std::move(right), n_right, depth + 1);
    return index;
  }

  // Splits the events between the children, keeping their order. A triangle
  // on both sides is clipped to each child: where it misses a child's cell it
  // stays out of it, elsewhere it gets new events for its clipped box, sorted
  // and merged in.
  void partition(const EventLists& events, const Split& split, const Bounds3& left_box, const Bounds3& right_box,
                 EventLists& left, EventLists& right, std::size_t& n_left, std::size_t& n_right) {
    // The triangles' extent in this node along the split axis, from their events.
    for (const Event& e : events[split.axis]) {
      if (e.type != EventType::End) extent_lo_[e.triangle] = e.position;
      if (e.type != EventType::Start) extent_hi_[e.triangle] = e.position;
    }
    std::vector<std::uint32_t> straddling;
    std::size_t left_only = 0, right_only = 0;
    for (const Event& e : events[split.axis]) {
      if (e.type == EventType::End) continue;
      const Side side = extent_hi_[e.triangle] < split.position  ? Left
                        : extent_lo_[e.triangle] > split.position ? Right
                                                                  : Both;
      side_[e.triangle] = side;
      left_only += side == Left;
      right_only += side == Right;
      if (side == Both) straddling.push_back(e.triangle);
    }
    EventLists new_left, new_right;
    for (std::uint32_t t : straddling) {
      const std::array<glm::vec3, 3> corners = {mesh_.positions[mesh_.triangles[t][0]],
                                                 mesh_.positions[mesh_.triangles[t][1]],
                                                 mesh_.positions[mesh_.triangles[t][2]]};
      if (const auto box = clipped_bounds(corners, left_box)) {
        append_events(*box, t, new_left);
        ++n_left;
      }
      if (const auto box = clipped_bounds(corners, right_box)) {
        append_events(*box, t, new_right);
        ++n_right;
      }
    }
    n_left += left_only;
    n_right += right_only;
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<Event> left_events, right_events;
      left_events.reserve(2 * left_only);
      right_events.reserve(2 * right_only);
      for (const Event& e : events[axis]) {
        if (side_[e.triangle] == Left) left_events.push_back(e);
        if (side_[e.triangle] == Right) right_events.push_back(e);
      }
      left[axis] = merged(left_events, new_left[axis]);
      right[axis] = merged(right_events, new_right[axis]);
    }
  }

  // The union of a sorted list and an unsorted one, sorted.
  static std::vector<Event> merged(const std::vector<Event>& sorted, std::vector<Event>& extra) {
    std::sort(extra.begin(), extra.end());
    std::vector<Event> out(sorted.size() + extra.size());
    std::merge(sorted.begin(), sorted.end(), extra.begin(), extra.end(), out.begin());
    return out;
  }

  void make_leaf(KdTree& tree, const Bounds3& box, const std::vector<Event>& events) {
    const std::size_t first = tree.leaf_triangles.size();
    for (const Event& e : events)
      if (e.type != EventType::End) tree.leaf_triangles.push_back(e.triangle);
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
  std::vector<Bounds3> triangle_boxes_;
  // Scratch, per triangle, for the node being split.
  std::vector<Side> side_;
  std::vector<float> extent_lo_, extent_hi_;
  int max_depth_ = 0;
  float min_width_ = 0.0f;
  double root_area_ = 0.0;
};

}  // namespace

KdTree build_kd_tree(const TriangleMesh& mesh, const KdBuildOptions& options) {
  return Builder(mesh, options).build();
}

}  // namespace mbao
