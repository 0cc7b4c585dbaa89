// A node's split events dealt out to its two children, the partition step of
// Wald and Havran's O(N log N) build (2006): which side of the split each
// triangle is on, new events for the triangles on both sides (clipped to each
// child's cell, or their boxes cut at the split), and the children's events
// merged in order from the parent's, each axis in one pass.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "accel/sah_sweep.h"
#include "accel/split_events.h"
#include "scene/bounds.h"

namespace mbao {

// A mesh's triangles in the tree's frame: positions less the tree's origin.
struct TreeFrameMesh {
  const std::vector<glm::vec3>& positions;
  const std::vector<glm::uvec3>& triangles;
  glm::vec3 origin;

  glm::vec3 position(std::uint32_t vertex) const { return positions[vertex] - origin; }
  std::array<glm::vec3, 3> corners(std::uint32_t t) const {
    const glm::uvec3& v = triangles[t];
    return {position(v[0]), position(v[1]), position(v[2])};
  }
};

enum Side : std::uint8_t { Below, Above, Both };

// What a thread needs while it partitions a node, reused from node to node.
struct PartitionScratch {
  // `side` is zeroed once (classify reads a triangle's side before it
  // selects what to write) and written for every triangle of a node before
  // its side is used. `straddlers` has one slot more than a node can list: the
  // partition writes a triangle before it knows whether to keep it.
  explicit PartitionScratch(std::size_t triangles);
  void clear_new_events();

  std::unique_ptr<Side[]> side;                 // by triangle index
  std::unique_ptr<std::uint32_t[]> straddlers;  // of a node, to be clipped
  // New events of straddling triangles, by axis, before they are merged in.
  std::array<std::vector<Event>, 3> clipped_below, clipped_above;
};

// A split's children: first their triangle counts (from partition_clipping or
// partition_cutting_boxes), then their events (fill_children).
struct Children {
  NodeEvents below, above;
  std::size_t n_below = 0, n_above = 0;
  // The split axis where straddlers' boxes were cut (their events along the
  // other axes then go to both children), or -1 where they were clipped.
  int cut_axis = -1;
};

// Which side of the split each triangle goes to (in scratch.side), and the
// children's triangle counts. A triangle on both sides is clipped to each
// child: where it misses a child's cell it stays out of it, elsewhere it gets
// new events for its clipped box (in scratch, for fill_children).
Children partition_clipping(const NodeEvents& events, const Split& split, const Bounds3& below_box,
                            const Bounds3& above_box, const TreeFrameMesh& mesh, PartitionScratch& scratch);

// Like partition_clipping, but a straddling triangle's box is cut at the split:
// its interval [s, e] along the split axis becomes [s, split] below and
// [split, e] above (planar where that is one point), and its events along the
// other axes go to both children as they are.
Children partition_cutting_boxes(const NodeEvents& events, const Split& split, PartitionScratch& scratch);

// Allocates the children's events and merges them in, axis by axis, from the
// parent's events and the sides and new events that a partition left in
// scratch. Each of the parent's axes is released once merged.
void fill_children(NodeEvents& parent, PartitionScratch& scratch, Children& children);

}  // namespace mbao
