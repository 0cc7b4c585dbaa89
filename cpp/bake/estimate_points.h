// Where a bake's estimates are taken (SPEC 6): for each target (a vertex, a
// texel) and each of its estimates, one point on the surface.
#pragma once

#include <algorithm>
#include <array>
#include <utility>
#include <cstdint>
#include <optional>

#include "mbao/philox.h"

namespace mbao {

// A point on triangle `triangle` with barycentric weights b1, b2 of its second and third corners.
struct SurfacePoint {
  std::uint32_t triangle;
  float b1, b2;
};

// The four uniform numbers in [0, 1) of estimate `sample` of `target`: a pure
// function of the two and the seed (SPEC 6.6). The kernels key a camera
// sample's jitter the same way (bounce 0, node 0), which a bake has no use
// for, so an estimate's point and its path share no random numbers.
inline std::array<double, 4> estimate_random(std::uint32_t target, std::uint32_t sample, std::uint64_t seed) {
  const Philox4x32 bits =
      philox4x32_10(Philox4x32{{target, sample, 0u, 0u}}, std::uint32_t(seed), std::uint32_t(seed >> 32));
  constexpr double kScale = 1.0 / 4294967296.0;
  return {bits.v[0] * kScale, bits.v[1] * kScale, bits.v[2] * kScale, bits.v[3] * kScale};
}

// The entry of [first, last) that u in [0, 1) picks with probability
// proportional to its part of the running total `area_so_far` (entries of zero
// part are never picked), and what is left of u within that part: uniform in
// [0, 1) too, so it can make the next choice.
template <typename Iterator>
std::pair<Iterator, double> pick_by_area(Iterator first, Iterator last, double u) {
  const double pick = u * (last - 1)->area_so_far;
  Iterator chosen =
      std::upper_bound(first, last, pick, [](double x, const auto& entry) { return x < entry.area_so_far; });
  if (chosen == last) --chosen;  // pick rounded up to the total
  const double before = chosen == first ? 0.0 : (chosen - 1)->area_so_far;
  return {chosen, std::clamp((pick - before) / (chosen->area_so_far - before), 0.0, 1.0)};
}

// The points of one kind of bake.
class EstimatePoints {
 public:
  virtual ~EstimatePoints() = default;
  // How many targets there are.
  virtual std::size_t targets() const = 0;
  // Whether `target` holds surface to draw points on; point() gives none where it does not.
  virtual bool has_surface(std::size_t target) const = 0;
  // The point of one estimate of `target` from its four uniform numbers, or
  // none where the target holds no surface.
  virtual std::optional<SurfacePoint> point(std::size_t target, const std::array<double, 4>& random) const = 0;
};

}  // namespace mbao
