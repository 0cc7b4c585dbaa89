// The surface area heuristic's sweep of a kd-tree node (kd_tree_builder.cpp):
// the cheapest split plane over each axis's sorted events.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "accel/kd_tree.h"
#include "accel/split_events.h"

namespace mbao {

// A plane that splits a node: its axis, position and cost.
struct Split {
  int axis = -1;
  float position = 0.0f;
  double cost = std::numeric_limits<double>::infinity();
  // Where the sweep of `axis` priced it: -1 below all events, i between
  // events i - 1 and i, the event count above all. Of planes of equal cost
  // the first in the order (axis, sweep_index) wins.
  std::ptrdiff_t sweep_index = 0;

  bool is_beaten_by(const Split& other) const {
    if (other.cost != cost) return other.cost < cost;
    return other.axis < axis || (other.axis == axis && other.sweep_index < sweep_index);
  }
};

// The sweep's blocks of events, reused from node to node: counts before each
// (ends also past the last), and the least cost of a plane in each.
struct SweepBlocks {
  std::vector<std::size_t> starts_before_block, ends_before_block;
  std::vector<double> block_bound;
};

// The cheapest plane across `box` for a node of `n` triangles with `events`,
// each child at least `min_width` wide, its cost divided by the node's half
// area; none (axis -1) where no plane fits.
Split find_split(const Bounds3& box, const NodeEvents& events, std::size_t n, const KdBuildOptions& options,
                 float min_width, SweepBlocks& scratch);

}  // namespace mbao
