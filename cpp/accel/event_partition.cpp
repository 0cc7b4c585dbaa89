#include "accel/event_partition.h"

#include <algorithm>

#include "accel/triangle_clip.h"

namespace mbao {
namespace {

// Which side of the split each triangle of the node is on, from one pass
// over the split axis's events in order: a start below the split makes a
// triangle straddle until its end, if that is below too, makes it Below;
// an end at or above the split leaves what its start made it. Positions
// compare as their order bits, and the side is selected, not branched to.
void classify(const NodeEvents& events, const Split& split, Side* side) {
  const std::uint32_t split_order = Event::make(split.position, EventType::End, 0).position_order();
  for (const Event *e = events.begin(split.axis), *end = events.end(split.axis); e != end; ++e) {
    const std::uint32_t t = e->triangle(), order = e->position_order();
    const EventType type = e->type();
    const bool below = order < split_order;
    const bool above = order > split_order;
    const Side made = below ? (type == EventType::Start ? Both : Below) : (above ? Above : Both);
    const Side before = side[t];
    side[t] = below || type != EventType::End ? made : before;
  }
}

// Adds the events of `box`, the part of triangle t in a child's cell, if
// there is one; returns whether there was.
bool add_events(std::uint32_t t, const std::optional<Bounds3>& box, std::array<std::vector<Event>, 3>& out) {
  if (!box) return false;
  for (std::size_t axis = 0; axis < 3; ++axis)
    for_box_events(int(axis), *box, t, [&](const Event& e) { out[axis].push_back(e); });
  return true;
}

// The children's events along `axis`: the parent's events of triangles
// wholly on one side go to that side (and with `both_to_both`, those of
// triangles on both sides to both), merged with the clipped triangles' new
// events. One pass over the parent's events fills both children.
void merge_sides(NodeEvents& parent, int axis, const Side* side, std::vector<Event>& clipped_below,
                 std::vector<Event>& clipped_above, Children& children, bool both_to_both) {
  // A sentinel above every event ends each run of new events without a bounds check.
  for (std::vector<Event>* clipped : {&clipped_below, &clipped_above}) {
    sort_events(clipped->data(), clipped->data() + clipped->size());
    clipped->push_back(Event::after_all());
  }
  const Event *extra_below = clipped_below.data(), *extra_above = clipped_above.data();
  Event* below = children.below.begin(axis);
  Event* above = children.above.begin(axis);
  // The side an event goes to is a coin flip to the branch predictor: each
  // event is written to both children and kept where it belongs.
  const std::array<std::uint8_t, 3> keep_below{1, 0, both_to_both}, keep_above{0, 1, both_to_both};  // by Side
  // In chunks, each one's pages handed back once merged: the root's split
  // would otherwise hold its events along the axis and the children's whole.
  constexpr std::ptrdiff_t kChunk = std::ptrdiff_t(1) << 17;
  for (const Event *e = parent.begin(axis), *end = parent.end(axis); e != end;) {
    for (const Event* chunk_end = e + std::min(end - e, kChunk); e != chunk_end; ++e) {
      const Event event = *e;
      while (*extra_below < event) *below++ = *extra_below++;
      while (*extra_above < event) *above++ = *extra_above++;
      const Side s = side[event.triangle()];
      *below = event;
      below += keep_below[s];
      *above = event;
      above += keep_above[s];
    }
    parent.release_before(axis, e);
  }
  below = std::copy(extra_below, static_cast<const Event*>(&clipped_below.back()), below);
  above = std::copy(extra_above, static_cast<const Event*>(&clipped_above.back()), above);
  children.below.close_axis(axis, below);
  children.above.close_axis(axis, above);
}

}  // namespace

PartitionScratch::PartitionScratch(std::size_t triangles)
    : side(new Side[triangles]()), straddlers(new std::uint32_t[triangles + 1]) {}

void PartitionScratch::clear_new_events() {
  for (int axis = 0; axis < 3; ++axis) {
    clipped_below[axis].clear();
    clipped_above[axis].clear();
  }
}

Children partition_clipping(const NodeEvents& events, const Split& split, const Bounds3& below_box,
                            const Bounds3& above_box, const TreeFrameMesh& mesh, PartitionScratch& scratch) {
  Side* side = scratch.side.get();
  classify(events, split, side);
  scratch.clear_new_events();
  Children children;
  // Which side a triangle is on is a coin flip to the branch predictor:
  // the counts add comparisons, and each triangle is written to the list of
  // straddlers and kept there by moving its end past it.
  std::uint32_t* straddlers = scratch.straddlers.get();
  std::size_t n_straddlers = 0;
  for (const Event *e = events.begin(split.axis), *end = events.end(split.axis); e != end; ++e) {
    const std::uint32_t t = e->triangle();
    const bool begins = begins_triangle(e->type());
    const Side s = side[t];
    children.n_below += begins & (s == Below);
    children.n_above += begins & (s == Above);
    straddlers[n_straddlers] = t;
    n_straddlers += begins & (s == Both);
  }
  for (std::size_t i = 0; i < n_straddlers; ++i) {
    const std::uint32_t t = straddlers[i];
    const auto [below_part, above_part] = clipped_bounds_of_split(mesh.corners(t), below_box, above_box, split.axis);
    children.n_below += add_events(t, below_part, scratch.clipped_below);
    children.n_above += add_events(t, above_part, scratch.clipped_above);
  }
  return children;
}

Children partition_cutting_boxes(const NodeEvents& events, const Split& split, PartitionScratch& scratch) {
  Side* side = scratch.side.get();
  classify(events, split, side);
  scratch.clear_new_events();
  std::vector<Event>& below = scratch.clipped_below[std::size_t(split.axis)];
  std::vector<Event>& above = scratch.clipped_above[std::size_t(split.axis)];
  Children children;
  children.cut_axis = split.axis;
  for (const Event *e = events.begin(split.axis), *end = events.end(split.axis); e != end; ++e) {
    const std::uint32_t t = e->triangle();
    const EventType type = e->type();
    if (side[t] != Both) {
      (side[t] == Below ? children.n_below : children.n_above) += begins_triangle(type);
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
  return children;
}

void fill_children(NodeEvents& parent, PartitionScratch& scratch, Children& children) {
  children.below = NodeEvents(2 * children.n_below);
  children.above = NodeEvents(2 * children.n_above);
  for (int axis = 0; axis < 3; ++axis) {
    merge_sides(parent, axis, scratch.side.get(), scratch.clipped_below[std::size_t(axis)],
                scratch.clipped_above[std::size_t(axis)], children,
                children.cut_axis >= 0 && axis != children.cut_axis);
    parent.release(axis);
  }
}

}  // namespace mbao
