#include "accel/sah_sweep.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace mbao {
namespace {

// Events per block of the sweep's pruning, and the fewest events along an
// axis for which the blocks' bounds pay.
constexpr std::size_t kSweepBlock = 16;
constexpr std::size_t kMinEventsToPrune = 4 * kSweepBlock;

// The axes by decreasing extent, of equal ones the lower first.
std::array<int, 3> longest_first(const glm::dvec3& extent) {
  std::array<int, 3> axes{0, 1, 2};
  const auto order = [&](int& a, int& b) {
    if (extent[b] > extent[a]) std::swap(a, b);
  };
  order(axes[0], axes[1]);
  order(axes[1], axes[2]);
  order(axes[0], axes[1]);
  return axes;
}

// The SAH cost of a plane across one axis of a node, times the node's half
// area: a child's half area is cap + (its width along the axis) * girth.
class AxisCost {
 public:
  AxisCost(const Bounds3& box, const glm::dvec3& extent, int axis, const KdBuildOptions& options, double half_area)
      : lo_(box.lo[axis]),
        hi_(box.hi[axis]),
        cap_(extent[(axis + 1) % 3] * extent[(axis + 2) % 3]),
        girth_(extent[(axis + 1) % 3] + extent[(axis + 2) % 3]),
        traversal_(options.traversal_cost * half_area),
        intersection_(options.intersection_cost),
        empty_factor_(1.0 - options.empty_bonus) {}

  double operator()(float position, std::size_t n_below, std::size_t n_above) const {
    const double lambda = (n_below == 0 || n_above == 0) ? empty_factor_ : 1.0;
    return priced(position - lo_, hi_ - position, n_below, n_above, lambda);
  }

  // operator() of a plane between two events, which has triangles on both
  // sides: no empty bonus to choose, the same cost.
  double between_events(float position, std::size_t n_below, std::size_t n_above) const {
    assert(n_below > 0 && n_above > 0);
    return priced(position - lo_, hi_ - position, n_below, n_above);
  }

  // At most the cost of any plane from `lowest` to `highest` with at least
  // n_below triangles below and n_above above (the cost grows with each);
  // -infinity where costs with negative constants need not grow.
  double least(float lowest, float highest, std::size_t n_below, std::size_t n_above) const {
    if (intersection_ < 0.0 || empty_factor_ < 0.0) return -std::numeric_limits<double>::infinity();
    const double lambda = (n_below == 0 || n_above == 0) ? std::min(empty_factor_, 1.0) : 1.0;
    return priced(std::max(0.0, lowest - lo_), std::max(0.0, hi_ - highest), n_below, n_above, lambda);
  }

 private:
  // One formula for costs and bounds, so that a bound rounds as the costs it bounds.
  double priced(double width_below, double width_above, std::size_t n_below, std::size_t n_above, double lambda) const {
    return lambda * priced(width_below, width_above, n_below, n_above);
  }
  double priced(double width_below, double width_above, std::size_t n_below, std::size_t n_above) const {
    const double area_below = cap_ + width_below * girth_;
    const double area_above = cap_ + width_above * girth_;
    return traversal_ + intersection_ * (area_below * as_double(n_below) + area_above * as_double(n_above));
  }

  // Counts are far below 2^63: through a signed integer the conversion is one
  // instruction, against several for an unsigned one (the sweep prices
  // tens of millions of planes).
  static double as_double(std::size_t count) { return double(std::int64_t(count)); }

  double lo_, hi_, cap_, girth_, traversal_, intersection_, empty_factor_;
};

// Cuts an axis's events into blocks of kSweepBlock and bounds the cost of
// every plane the sweep prices in each (those between events i - 1 and i
// for i in the block): such a plane lies from event i - 1's position less
// min_width to event i's plus min_width, with no fewer triangles below
// than start before the block, and no fewer above than end in or after it.
// Leaves the counts before each block and its bound in scratch.
void sweep_block_bounds(const Event* first, std::size_t count, std::size_t n, const AxisCost& cost, float min_width,
                        SweepBlocks& scratch) {
  const std::size_t blocks = (count + kSweepBlock - 1) / kSweepBlock;
  scratch.starts_before_block.resize(blocks);
  scratch.ends_before_block.resize(blocks + 1);
  std::size_t starts = 0, ends = 0;
  for (std::size_t block = 0; block < blocks; ++block) {
    scratch.starts_before_block[block] = starts;
    scratch.ends_before_block[block] = ends;
    const std::size_t end = std::min(count, (block + 1) * kSweepBlock);
    for (std::size_t i = block * kSweepBlock; i < end; ++i) {
      const EventType type = first[i].type();
      starts += begins_triangle(type);
      ends += ends_triangle(type);
    }
  }
  scratch.ends_before_block[blocks] = ends;
  scratch.block_bound.resize(blocks);
  for (std::size_t block = 0; block < blocks; ++block) {
    const std::size_t begin = block * kSweepBlock, end = std::min(count, begin + kSweepBlock);
    const float lowest = first[begin > 0 ? begin - 1 : 0].position() - min_width;
    const float highest = first[end - 1].position() + min_width;
    scratch.block_bound[block] =
        cost.least(lowest, highest, scratch.starts_before_block[block], n - scratch.ends_before_block[block + 1]);
  }
}

}  // namespace

// Sweeps each axis's sorted events. Between two event positions p < q the
// planes p + min_width (what ends at p goes below) and q - min_width (what
// starts at q goes above) are candidates, with the same counts on either
// side; below the first position and above the last one, the planes that
// cut off empty space. The partition itself is exact. Costs are compared
// times the node's half area, which saves a division per candidate.
//
// Most planes cannot win, and whole runs of them can be shown not to from
// a bound on their cost: an axis whose planes between events all cost more
// than the best found is not swept, and a long one is swept in blocks
// (sweep_block_bounds), the block of least bound first, then each other
// one whose bound does not exceed the best cost found by then. The longest
// axis, where the best plane usually lies, goes first. The plane found is
// the one a full sweep of the axes in order finds: Split::is_beaten_by
// orders ties as that sweep meets them. (Sponza: 49% of the events are
// swept, among them the 39% in axes too short for blocks; 0.93 of the
// instructions.)
Split find_split(const Bounds3& box, const NodeEvents& events, std::size_t n, const KdBuildOptions& options,
                 float min_width, SweepBlocks& scratch) {
  Split best;
  const glm::dvec3 extent = glm::dvec3(box.hi) - glm::dvec3(box.lo);
  const double half_area = extent.x * extent.y + extent.y * extent.z + extent.z * extent.x;
  if (!(half_area > 0.0)) return best;
  const bool prune = options.prune_sweep;
  for (const int axis : prune ? longest_first(extent) : std::array<int, 3>{0, 1, 2}) {
    const AxisCost cost(box, extent, axis, options, half_area);
    const float lo = box.lo[axis], hi = box.hi[axis];
    if (hi - lo < 2.0f * min_width) continue;
    const Event* first = events.begin(axis);
    const std::size_t count = events.size(axis);
    if (count == 0) continue;
    const auto fits = [&](float position) { return position - lo >= min_width && hi - position >= min_width; };
    const auto consider = [&](float position, double price, std::ptrdiff_t index) {
      const Split candidate{axis, position, price, index};
      if (best.is_beaten_by(candidate)) best = candidate;
    };
    const float below_all = first->position() - min_width, above_all = first[count - 1].position() + min_width;
    if (fits(below_all)) consider(below_all, cost(below_all, 0, n), -1);
    if (fits(above_all)) consider(above_all, cost(above_all, n, 0), std::ptrdiff_t(count));
    // Between two positions the cost is linear in the plane's position,
    // rising where more triangles lie below than above: only the cheaper
    // end is priced (the lower one on a tie), or the other one where the
    // cheaper does not fit. Events [from, to), after `starts` starts and
    // `ends` ends (planar events count as both).
    const auto sweep = [&](std::size_t from, std::size_t to, std::size_t starts, std::size_t ends) {
      const Event* previous = first + (from > 0 ? from - 1 : 0);
      std::uint32_t previous_order = previous->position_order();
      float previous_position = previous->position();
      for (std::size_t i = from; i < to; ++i) {
        const Event e = first[i];
        const std::uint32_t order = e.position_order();
        if (order != previous_order) {
          const float position = e.position();
          const float left = previous_position + min_width, right = position - min_width;
          previous_order = order;
          previous_position = position;
          const std::size_t n_below = starts, n_above = n - ends;
          // Which end is cheaper is a coin flip to the branch predictor:
          // picked by index, not by branch.
          const bool take_right = (n_below != n_above) & ((n_below > n_above) != (left <= right));
          const float ends_of_gap[2] = {left, right};
          const float cheaper = ends_of_gap[take_right], dearer = ends_of_gap[!take_right];
          const float chosen = fits(cheaper) ? cheaper : dearer;
          if (fits(chosen)) consider(chosen, cost.between_events(chosen, n_below, n_above), std::ptrdiff_t(i));
        }
        starts += begins_triangle(e.type());
        ends += ends_triangle(e.type());
      }
    };
    // The margin covers the rounding of costs and bounds.
    const auto cannot_win = [&](double bound) { return bound > best.cost + std::abs(best.cost) * 0x1p-30; };
    // A plane between events has a triangle on either side (event 0 starts
    // one, the last ends one) and each triangle on one side at least.
    if (prune && cannot_win(cost.least(lo, hi, n - 1, 1))) continue;
    if (!prune || count < kMinEventsToPrune) {
      sweep(0, count, 0, 0);
      continue;
    }
    sweep_block_bounds(first, count, n, cost, min_width, scratch);
    const auto sweep_block = [&](std::size_t block) {
      if (cannot_win(scratch.block_bound[block])) return;
      sweep(block * kSweepBlock, std::min(count, (block + 1) * kSweepBlock), scratch.starts_before_block[block],
            scratch.ends_before_block[block]);
    };
    const std::size_t blocks = scratch.block_bound.size();
    const std::size_t most_promising = std::size_t(
        std::min_element(scratch.block_bound.begin(), scratch.block_bound.end()) - scratch.block_bound.begin());
    sweep_block(most_promising);
    for (std::size_t block = 0; block < blocks; ++block)
      if (block != most_promising) sweep_block(block);
  }
  best.cost /= half_area;
  return best;
}

}  // namespace mbao
