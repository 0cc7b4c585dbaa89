// Split events of the SAH sweep (Wald and Havran 2006): where a triangle's box
// starts or ends along an axis, or where it lies when it is flat along it.
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include "core/sorting_network.h"
#include "scene/bounds.h"

namespace mbao {

enum class EventType : std::uint32_t { End = 0, Planar = 1, Start = 2 };

// A planar event both begins and ends its triangle: counting the events that
// begin triangles counts each triangle once, and so does counting those that
// end them.
inline bool begins_triangle(EventType type) { return type != EventType::End; }
inline bool ends_triangle(EventType type) { return type != EventType::Start; }

// Triangle indices share a word with the event type.
constexpr std::uint32_t kMaxEventTriangle = (1u << 30) - 1u;

// 8 bytes: the build streams hundreds of millions of these. One 64-bit word
// whose integer order is the events' order: the position's bits, mapped so that
// they order as the floats do, above the type, above the triangle. Sorting and
// merging thus compare one integer, and equal positions have equal top halves.
struct Event {
  std::uint64_t bits;

  static Event make(float position, EventType type, std::uint32_t triangle) {
    const std::uint32_t key = (std::uint32_t(type) << 30) | triangle;
    return {(std::uint64_t(ordered_bits(position)) << 32) | key};
  }
  // Orders after every event of a real position (its top half would be a NaN's).
  static Event after_all() { return {~std::uint64_t(0)}; }
  float position() const { return float_of_ordered(std::uint32_t(bits >> 32)); }
  std::uint32_t position_order() const { return std::uint32_t(bits >> 32); }
  EventType type() const { return EventType((bits >> 30) & 3u); }
  std::uint32_t triangle() const { return std::uint32_t(bits) & kMaxEventTriangle; }

 private:
  // Positive floats get the top bit set, negative ones all bits flipped; -0 is
  // made +0 first so that the two zeros are one position.
  static std::uint32_t ordered_bits(float position) {
    const float canonical = position + 0.0f;
    std::uint32_t b;
    std::memcpy(&b, &canonical, sizeof b);
    return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
  }
  static float float_of_ordered(std::uint32_t o) {
    const std::uint32_t b = (o & 0x80000000u) ? (o & 0x7fffffffu) : ~o;
    float position;
    std::memcpy(&position, &b, sizeof position);
    return position;
  }
};

// By position; at one position ends before planar before starts (what the
// sweep counts relies on), then by triangle, so that the order is total and
// the tree the same whatever sorted the events.
inline bool operator<(const Event& a, const Event& b) { return a.bits < b.bits; }

// Sorts events that were made in increasing triangle order (as the root's are)
// into the events' order. A stable radix sort on the bits above the triangle
// (position and type) leaves events with equal ones in the order they were
// made, which is by triangle, so the result is what std::sort gives, in three
// linear passes instead of n log n comparisons.
inline void sort_events_made_by_triangle(Event* first, Event* last) {
  constexpr int kDigitBits = 12;
  constexpr std::size_t kDigits = std::size_t(1) << kDigitBits;
  const std::size_t n = std::size_t(last - first);
  std::unique_ptr<Event[]> buffer(new Event[n]);
  Event* from = first;
  Event* to = buffer.get();
  for (int shift = 30; shift < 64; shift += kDigitBits) {
    const auto digit = [shift](const Event& e) { return std::size_t(e.bits >> shift) & (kDigits - 1); };
    std::vector<std::size_t> slot(kDigits, 0);
    for (std::size_t i = 0; i < n; ++i) ++slot[digit(from[i])];
    if (n > 0 && slot[digit(from[0])] == n) continue;  // one digit value: the pass would copy
    std::size_t start = 0;
    for (std::size_t& s : slot) start += std::exchange(s, start);
    for (std::size_t i = 0; i < n; ++i) to[slot[digit(from[i])]++] = from[i];
    std::swap(from, to);
  }
  if (from != first) std::copy(from, from + n, first);
}

// Sorts up to N = 2^k events through a sorting network on their bits, the
// keys past the last padded with after_all's.
template <std::size_t N>
void sort_few_events(Event* first, std::size_t n) {
  std::uint64_t keys[N];
  for (std::size_t i = 0; i < N; ++i) keys[i] = i < n ? first[i].bits : Event::after_all().bits;
  network_sort(keys);
  for (std::size_t i = 0; i < N; ++i)
    if (i < n) first[i].bits = keys[i];
}

// Sorts events in no particular order. The new events of a node's clipped
// triangles come a few to a few tens at a time, in an order the branch
// predictor cannot follow: up to 32 go through a sorting network, more
// through std::sort.
inline void sort_events(Event* first, Event* last) {
  const std::size_t n = std::size_t(last - first);
  if (n <= 4) {
    sort_few_events<4>(first, n);
  } else if (n <= 8) {
    sort_few_events<8>(first, n);
  } else if (n <= 16) {
    sort_few_events<16>(first, n);
  } else if (n <= 32) {
    sort_few_events<32>(first, n);
  } else {
    std::sort(first, last);
  }
}

// How many events `box` has along `axis`: a start and an end, or one planar
// event where it is flat.
inline std::size_t box_event_count(int axis, const Bounds3& box) { return box.lo[axis] == box.hi[axis] ? 1 : 2; }

// Hands `push` the box_event_count(axis, box) events of `box` along `axis`.
template <class Push>
void for_box_events(int axis, const Bounds3& box, std::uint32_t triangle, Push&& push) {
  if (box_event_count(axis, box) == 1) {
    push(Event::make(box.lo[axis], EventType::Planar, triangle));
  } else {
    push(Event::make(box.lo[axis], EventType::Start, triangle));
    push(Event::make(box.hi[axis], EventType::End, triangle));
  }
}

// The events of one node: one sorted run per axis, the three runs in one
// buffer of a capacity fixed up front (six per triangle at most). Not a
// vector: the build pushes each event once per level, and the buffer needs
// neither zeroing nor capacity checks.
class NodeEvents {
 public:
  NodeEvents() = default;
  // One slot more than asked for: a writer may store an event before it knows
  // whether to keep it (see next_slot).
  explicit NodeEvents(std::size_t capacity) : events_(new Event[capacity + 1]), capacity_(capacity) {}

  const Event* begin(int axis) const { return events_.get() + start_[std::size_t(axis)]; }
  const Event* end(int axis) const { return events_.get() + start_[std::size_t(axis) + 1]; }
  Event* begin(int axis) { return events_.get() + start_[std::size_t(axis)]; }
  Event* end(int axis) { return events_.get() + start_[std::size_t(axis) + 1]; }
  std::size_t size(int axis) const { return start_[std::size_t(axis) + 1] - start_[std::size_t(axis)]; }

  // Filling one axis after the other: write from next_slot() on, then close
  // the axis at the pointer past the last event kept.
  Event* next_slot() { return events_.get() + size_; }
  void close_axis(int axis, const Event* filled_to) {
    size_ = std::size_t(filled_to - events_.get());
    assert(size_ <= capacity_);
    start_[std::size_t(axis) + 1] = size_;
  }

  // Filling in place, the axes at once: lay the runs out with these sizes,
  // then write each from begin(axis).
  void lay_out(const std::array<std::size_t, 3>& sizes) {
    for (std::size_t axis = 0; axis < 3; ++axis) start_[axis + 1] = start_[axis] + sizes[axis];
    size_ = start_[3];
    assert(size_ <= capacity_);
  }

 private:
  std::unique_ptr<Event[]> events_;
  [[maybe_unused]] std::size_t capacity_ = 0;  // for the asserts
  std::size_t size_ = 0;
  std::array<std::size_t, 4> start_{};
};

}  // namespace mbao
