// The kd-tree build's split events: one integer comparison orders them, and
// every way the build sorts them (radix, buckets, sorting networks) gives
// that full order.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "accel/split_events.h"

namespace mbao {
namespace {

// The sweep and the merges rely on one integer comparison giving the events'
// order: by position as floats order (the two zeros one position), then ends
// before planars before starts, then by triangle.
TEST(SplitEvent, IntegerOrderIsPositionThenTypeThenTriangle) {
  const std::vector<float> positions{-std::numeric_limits<float>::max(),
                                     -1e20f,
                                     -2.0f,
                                     -1.0f,
                                     -1e-30f,
                                     -std::numeric_limits<float>::denorm_min(),
                                     0.0f,
                                     std::numeric_limits<float>::denorm_min(),
                                     1e-30f,
                                     1.0f,
                                     3.5f,
                                     1e30f,
                                     std::numeric_limits<float>::max()};
  std::vector<Event> events;
  for (float p : positions)
    for (EventType type : {EventType::End, EventType::Planar, EventType::Start})
      for (std::uint32_t triangle : {0u, 7u, kMaxEventTriangle}) events.push_back(Event::make(p, type, triangle));
  EXPECT_TRUE(std::is_sorted(events.begin(), events.end()));
  for (std::size_t i = 1; i < events.size(); ++i) EXPECT_LT(events[i - 1], events[i]) << "at " << i;
  for (const Event& e : events) EXPECT_EQ(Event::make(e.position(), e.type(), e.triangle()).bits, e.bits);
  EXPECT_EQ(Event::make(-0.0f, EventType::Start, 3).bits, Event::make(0.0f, EventType::Start, 3).bits);
  EXPECT_LT(events.back(), Event::after_all());
}

// Boxes along one axis around `centre`, with many equal positions (grid
// values; both zeros where the centre is 0), planar ones, and a third
// anywhere within `spread`, their events made triangle by triangle.
std::vector<Event> root_like_events(std::uint32_t triangles, float centre, float spread) {
  std::mt19937 random(7);
  std::uniform_int_distribution<int> grid(-40, 40);
  std::uniform_real_distribution<float> anywhere(-spread, spread);
  const auto on_grid = [&] { return centre + spread / 64.0f * float(grid(random)); };
  std::vector<Event> events;
  for (std::uint32_t t = 0; t < triangles; ++t) {
    const float a = t % 3 == 0 ? centre + anywhere(random) : on_grid();
    const float b = t % 5 == 0 ? a : (t % 7 == 0 && centre == 0.0f ? -0.0f : on_grid());
    for_interval_events(std::min(a, b), std::max(a, b), t, [&events](const Event& e) { events.push_back(e); });
  }
  return events;
}

// The root's events are made triangle by triangle and radix-sorted on their
// position and type alone: the result must be the full order all the same,
// for any count (the digits' width follows it) and whether the positions
// differ in every digit, in the low ones alone (a few float steps apart, as
// in a bucket of make_sorted_events) or not at all.
TEST(SplitEvent, RadixSortOfEventsMadeByTriangleIsTheFullOrder) {
  for (const std::uint32_t triangles : {1u, 7u, 40u, 300u, 20000u})
    for (const auto& [centre, spread] : {std::pair{0.0f, 1e6f}, {1.0f, 1e-5f}, {3.0f, 0.0f}}) {
      std::vector<Event> events = root_like_events(triangles, centre, spread);
      std::vector<Event> expected = events;
      std::sort(expected.begin(), expected.end());
      sort_events_made_by_triangle(events.data(), events.data() + events.size());
      ASSERT_EQ(events.size(), expected.size());
      for (std::size_t i = 0; i < events.size(); ++i)
        ASSERT_EQ(events[i].bits, expected[i].bits)
            << triangles << " triangles, " << centre << " +- " << spread << ", at " << i;
    }
}

// make_sorted_events buckets the events by the top bits of their position
// before sorting each bucket: the full order too, whether the positions span
// many binades and both signs (crowded buckets) or a few float steps (a
// position to a bucket), and `make` is called twice over the same events.
TEST(SplitEvent, MakingSortedEventsGivesTheFullOrder) {
  for (const auto& [centre, spread] : {std::pair{0.0f, 1e6f}, {0.0f, 10.0f}, {1.0f, 1e-5f}}) {
    const std::vector<Event> made = root_like_events(20000, centre, spread);
    float lowest = made.front().position(), highest = lowest;
    for (const Event& e : made) {
      lowest = std::min(lowest, e.position());
      highest = std::max(highest, e.position());
    }
    int calls = 0;
    const auto make = [&](auto&& push) {
      ++calls;
      for (const Event& e : made) push(e);
    };
    std::vector<Event> events(made.size());
    const Event* end = make_sorted_events(make, lowest, highest, events.data());
    std::vector<Event> expected = made;
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(calls, 2);
    ASSERT_EQ(std::size_t(end - events.data()), expected.size()) << centre << " +- " << spread;
    for (std::size_t i = 0; i < events.size(); ++i)
      ASSERT_EQ(events[i].bits, expected[i].bits) << centre << " +- " << spread << ", at " << i;
  }
}

// A network sorts every input if it sorts every input of 0s and 1s (Knuth's
// 0-1 principle): checked exhaustively for the networks on 4, 8 and 16 keys.
template <std::size_t N>
void expect_network_sorts_all_zero_one_inputs() {
  for (std::uint32_t pattern = 0; pattern < (1u << N); ++pattern) {
    std::uint64_t keys[N];
    for (std::size_t i = 0; i < N; ++i) keys[i] = (pattern >> i) & 1u;
    network_sort(keys);
    ASSERT_TRUE(std::is_sorted(std::begin(keys), std::end(keys))) << N << " keys, pattern " << pattern;
  }
}

TEST(SplitEvent, SortingNetworksSortEveryZeroOneInput) {
  expect_network_sorts_all_zero_one_inputs<4>();
  expect_network_sorts_all_zero_one_inputs<8>();
  expect_network_sorts_all_zero_one_inputs<16>();
}

// sort_events gives std::sort's order for every count the networks take and
// beyond, with repeated positions and planar events.
TEST(SplitEvent, SortEventsIsTheFullOrder) {
  std::mt19937 random(5);
  std::uniform_int_distribution<int> grid(-6, 6);
  for (std::size_t count = 0; count <= 40; ++count) {
    for (int trial = 0; trial < 200; ++trial) {
      std::vector<Event> events;
      for (std::uint32_t t = 0; events.size() < count; ++t) {
        Bounds3 box;
        const float a = 0.5f * float(grid(random)), b = t % 4 == 0 ? a : 0.5f * float(grid(random));
        box.lo = glm::vec3(std::min(a, b));
        box.hi = glm::vec3(std::max(a, b));
        for_box_events(0, box, t, [&events](const Event& e) { events.push_back(e); });
      }
      events.resize(count);
      std::shuffle(events.begin(), events.end(), random);
      std::vector<Event> expected = events;
      std::sort(expected.begin(), expected.end());
      sort_events(events.data(), events.data() + events.size());
      for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(events[i].bits, expected[i].bits) << count << " events";
    }
  }
}

}  // namespace
}  // namespace mbao
