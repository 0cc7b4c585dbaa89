// Split events of the SAH sweep (Wald and Havran 2006): where a triangle's box
// starts or ends along an axis, or where it lies when it is flat along it.
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "scene/bounds.h"

namespace mbao {

enum class EventType : std::uint32_t { End = 0, Planar = 1, Start = 2 };

// Triangle indices share a word with the event type.
constexpr std::uint32_t kMaxEventTriangle = (1u << 30) - 1u;

// 8 bytes: the build streams hundreds of millions of these.
struct Event {
  float position;
  std::uint32_t key;  // type in the top two bits, triangle below

  static Event make(float position, EventType type, std::uint32_t triangle) {
    return {position, (std::uint32_t(type) << 30) | triangle};
  }
  EventType type() const { return EventType(key >> 30); }
  std::uint32_t triangle() const { return key & kMaxEventTriangle; }
};

// By position; at one position ends before planar before starts (what the
// sweep counts relies on), then by triangle, so that the order is total and
// the tree the same whatever sorted the events.
inline bool operator<(const Event& a, const Event& b) {
  return a.position < b.position || (a.position == b.position && a.key < b.key);
}

// Hands `push` the events of `box` along `axis`: a start and an end, or one
// planar event.
template <class Push>
void for_box_events(int axis, const Bounds3& box, std::uint32_t triangle, Push&& push) {
  if (box.lo[axis] == box.hi[axis]) {
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
  explicit NodeEvents(std::size_t capacity) : events_(new Event[capacity]), capacity_(capacity) {}

  const Event* begin(int axis) const { return events_.get() + start_[std::size_t(axis)]; }
  const Event* end(int axis) const { return events_.get() + start_[std::size_t(axis) + 1]; }
  Event* begin(int axis) { return events_.get() + start_[std::size_t(axis)]; }
  Event* end(int axis) { return events_.get() + start_[std::size_t(axis) + 1]; }
  std::size_t size(int axis) const { return start_[std::size_t(axis) + 1] - start_[std::size_t(axis)]; }

  // Filling, one axis after the other: push the axis's events, then close it.
  void push(const Event& e) {
    assert(size_ < capacity_);
    events_[size_++] = e;
  }
  void close_axis(int axis) { start_[std::size_t(axis) + 1] = size_; }

  void push_box(int axis, const Bounds3& box, std::uint32_t triangle) {
    for_box_events(axis, box, triangle, [this](const Event& e) { push(e); });
  }

 private:
  std::unique_ptr<Event[]> events_;
  std::size_t capacity_ = 0, size_ = 0;
  std::array<std::size_t, 4> start_{};
};

}  // namespace mbao
