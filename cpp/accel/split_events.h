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

#include "core/page_block.h"
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
constexpr int kEventTriangleBits = 30;
constexpr std::uint32_t kMaxEventTriangle = (1u << kEventTriangleBits) - 1u;

// 8 bytes: the build streams hundreds of millions of these. One 64-bit word
// whose integer order is the events' order: the position's bits, mapped so that
// they order as the floats do, above the type, above the triangle. Sorting and
// merging thus compare one integer, and equal positions have equal top halves.
struct Event {
  std::uint64_t bits;

  static Event make(float position, EventType type, std::uint32_t triangle) {
    const std::uint32_t key = (std::uint32_t(type) << kEventTriangleBits) | triangle;
    return {(std::uint64_t(ordered_bits(position)) << 32) | key};
  }
  // Orders after every event of a real position (its top half would be a NaN's).
  static Event after_all() { return {~std::uint64_t(0)}; }
  float position() const { return float_of_ordered(std::uint32_t(bits >> 32)); }
  std::uint32_t position_order() const { return std::uint32_t(bits >> 32); }
  EventType type() const { return EventType((bits >> kEventTriangleBits) & 3u); }
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
// made, which is by triangle, so the result is what std::sort gives, in a few
// linear passes instead of n log n comparisons. Digits are about as wide as
// n has bits, up to 12, so that clearing and summing the counts costs no
// more than the pass over the events; only digits whose bits differ between
// the events get a pass (in a bucket of make_sorted_events, the top bits of
// the positions are the bucket's).
inline void sort_events_made_by_triangle(Event* first, Event* last) {
  constexpr int kMinDigitBits = 4, kMaxDigitBits = 12;
  const std::size_t n = std::size_t(last - first);
  std::uint64_t differing = 0;
  for (std::size_t i = 1; i < n; ++i) differing |= first[i].bits ^ first[0].bits;
  differing >>= kEventTriangleBits;
  if (differing == 0) return;  // one position and type: already in triangle order
  int digit_bits = kMinDigitBits;
  while (digit_bits < kMaxDigitBits && (std::size_t(1) << digit_bits) < n) ++digit_bits;
  const std::size_t digits = std::size_t(1) << digit_bits;
  std::unique_ptr<Event[]> buffer(new Event[n]);
  std::unique_ptr<std::size_t[]> slot(new std::size_t[digits]);
  Event* from = first;
  Event* to = buffer.get();
  for (int shift = 0; shift < 64 - kEventTriangleBits; shift += digit_bits) {
    if (((differing >> shift) & (digits - 1)) == 0) continue;  // the pass would copy
    const auto digit = [&](const Event& e) {
      return std::size_t(e.bits >> (kEventTriangleBits + shift)) & (digits - 1);
    };
    std::fill_n(slot.get(), digits, 0);
    for (std::size_t i = 0; i < n; ++i) ++slot[digit(from[i])];
    std::size_t start = 0;
    for (std::size_t d = 0; d < digits; ++d) start += std::exchange(slot[d], start);
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

// Hands `push` the events of a triangle whose box spans [lo, hi] along an
// axis: a start and an end, or one planar event where it is flat.
template <class Push>
void for_interval_events(float lo, float hi, std::uint32_t triangle, Push&& push) {
  if (lo == hi) {
    push(Event::make(lo, EventType::Planar, triangle));
  } else {
    push(Event::make(lo, EventType::Start, triangle));
    push(Event::make(hi, EventType::End, triangle));
  }
}

template <class Push>
void for_box_events(int axis, const Bounds3& box, std::uint32_t triangle, Push&& push) {
  for_interval_events(box.lo[axis], box.hi[axis], triangle, push);
}

// Writes the events that make(push) hands to `push` into `out` in the events'
// order, and returns the end. `make` is called twice and must hand over the
// same events each time, in increasing triangle order (as the root's are
// made), at positions from `lowest` to `highest`.
//
// With no buffer of the events' size: the first call counts the events by the
// top bits of their position's order above `lowest`'s, the second puts each
// in its bucket, in the order made, and each bucket is then sorted with a
// buffer of the bucket's size. (A buffer for each axis's events, sorted on
// their own thread, was the build's peak memory.)
template <class MakeEvents>
Event* make_sorted_events(const MakeEvents& make, float lowest, float highest, Event* out) {
  constexpr int kBucketBits = 12;
  const std::uint32_t low = Event::make(lowest, EventType::End, 0).position_order();
  const std::uint32_t range = Event::make(highest, EventType::End, 0).position_order() - low;
  int shift = 0;
  while ((range >> shift) >= (1u << kBucketBits)) ++shift;
  const auto bucket = [&](const Event& e) {
    assert(e.position_order() - low <= range);
    return std::size_t((e.position_order() - low) >> shift);
  };
  std::vector<std::size_t> next((range >> shift) + 1, 0);  // counts, then each bucket's next slot
  make([&](const Event& e) { ++next[bucket(e)]; });
  std::size_t start = 0;
  for (std::size_t& slot : next) start += std::exchange(slot, start);
  make([&](const Event& e) { out[next[bucket(e)]++] = e; });
  std::size_t first = 0;
  for (const std::size_t end : next) {
    sort_events_made_by_triangle(out + first, out + end);
    first = end;
  }
  return out + first;
}

// The events of one node: one sorted run per axis, each in room for two
// events per triangle, fixed up front. Not vectors: the build pushes each
// event once per level, and the runs need neither zeroing nor capacity checks.
//
// A large node's runs have a block each, so that its split can free them one
// by one as it fills the children (release): the root's split would
// otherwise hold the root's events and both children's at once. Those blocks
// are mapped pages of their own, which go back to the system when freed: from
// malloc, blocks of a few MiB stayed in the threads' heaps, hundreds of MB at
// the end of a large build. Smaller nodes' runs share one block, one
// allocation instead of three.
class NodeEvents {
 public:
  NodeEvents() = default;
  // Room for `capacity` events along each axis, and one slot more: a writer
  // may store an event before it knows whether to keep it.
  explicit NodeEvents(std::size_t capacity) : room_(capacity + 1) {
    apart_ = 3 * room_ * sizeof(Event) >= kMinBytesApart;
    if (!apart_) {
      shared_.reset(new Event[3 * room_]);
      for (std::size_t axis = 0; axis < 3; ++axis) first_[axis] = shared_.get() + axis * room_;
    } else {
      for (std::size_t axis = 0; axis < 3; ++axis) {
        pages_[axis] = PageBlock(room_ * sizeof(Event));
        first_[axis] = static_cast<Event*>(pages_[axis].data());
      }
    }
  }

  const Event* begin(int axis) const { return first_[std::size_t(axis)]; }
  const Event* end(int axis) const { return begin(axis) + size(axis); }
  Event* begin(int axis) { return first_[std::size_t(axis)]; }
  Event* end(int axis) { return begin(axis) + size(axis); }
  std::size_t size(int axis) const { return size_[std::size_t(axis)]; }

  // Filling an axis: write from begin(axis), then close it at the pointer
  // past the last event kept.
  void close_axis(int axis, const Event* filled_to) {
    size_[std::size_t(axis)] = std::size_t(filled_to - begin(axis));
    assert(size(axis) < room_);
  }

  // The axis's events before `read_to` are no longer needed: where they have a
  // block of their own, its pages before it go back to the system.
  void release_before(int axis, const Event* read_to) {
    if (apart_) pages_[std::size_t(axis)].release_before(std::size_t(read_to - begin(axis)) * sizeof(Event));
  }

  // The axis's events are no longer needed: frees them where they have a block
  // of their own. The axis is empty after.
  void release(int axis) {
    size_[std::size_t(axis)] = 0;
    if (!apart_) return;
    pages_[std::size_t(axis)] = PageBlock();
    first_[std::size_t(axis)] = nullptr;
  }

 private:
  // A node's events from this size on get a block per axis.
  static constexpr std::size_t kMinBytesApart = std::size_t(1) << 20;

  std::unique_ptr<Event[]> shared_;
  std::array<PageBlock, 3> pages_;
  std::array<Event*, 3> first_{};
  std::array<std::size_t, 3> size_{};
  std::size_t room_ = 0;  // events each run has room for
  bool apart_ = false;    // a block per axis
};

}  // namespace mbao
