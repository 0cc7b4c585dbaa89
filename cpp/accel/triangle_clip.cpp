#include "accel/triangle_clip.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <limits>

#include "core/outward_rounding.h"

namespace mbao {
namespace {

// A convex polygon: the triangle, cut by at most 6 planes, has at most 9 corners.
struct Polygon {
  std::array<glm::dvec3, 9> points;
  int size = 0;
};

// The axis a polygon is clipped along is a template parameter: a corner's
// coordinate along it is then a register, not a load from an index (a
// build clips millions of triangles).

// Where the edge from a to b, at signed distances da and db from the plane,
// crosses it: exactly on the plane, whatever the rounding of the rest.
template <int Axis>
glm::dvec3 crossing(const glm::dvec3& a, const glm::dvec3& b, double da, double db, double plane) {
  glm::dvec3 p = a + (b - a) * (da / (da - db));
  p[Axis] = plane;
  return p;
}

// Hands `keep` the corners of the part of `polygon` with
// sign * (p[Axis] - plane) <= 0, in order: each corner on that side and where
// each edge crosses the plane. Edges go from a corner to the next (the index
// wraps by a compare, not %, which is a division).
template <int Axis, class Keep>
void for_each_clipped_corner(const Polygon& polygon, double plane, double sign, Keep&& keep) {
  for (int i = 0, j = polygon.size > 1 ? 1 : 0; i < polygon.size; ++i, j = j + 1 < polygon.size ? j + 1 : 0) {
    const glm::dvec3& a = polygon.points[i];
    const glm::dvec3& b = polygon.points[j];
    const double da = sign * (a[Axis] - plane), db = sign * (b[Axis] - plane);
    if (da <= 0.0) keep(a);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) keep(crossing<Axis>(a, b, da, db, plane));
  }
}

// Keeps the part of `polygon` with sign * (p[Axis] - plane) <= 0.
template <int Axis>
void clip(Polygon& polygon, double plane, double sign) {
  Polygon in;  // only the corners in use: most polygons have 3 or 4
  in.size = polygon.size;
  std::copy_n(polygon.points.begin(), polygon.size, in.points.begin());
  polygon.size = 0;
  for_each_clipped_corner<Axis>(in, plane, sign, [&](const glm::dvec3& p) { polygon.points[polygon.size++] = p; });
}

// The least and greatest coordinate of the polygon's corners along Axis.
template <int Axis>
std::array<double, 2> extent_along(const Polygon& polygon) {
  double min = polygon.points[0][Axis], max = min;
  for (int i = 1; i < polygon.size; ++i) {
    min = std::min(min, polygon.points[i][Axis]);
    max = std::max(max, polygon.points[i][Axis]);
  }
  return {min, max};
}

// Clips `polygon` to lo <= p[Axis] <= hi. Most triangles a split straddles
// cross only the split plane: planes the polygon does not cross cost nothing.
template <int Axis>
void clip_to_slab(Polygon& polygon, double lo, double hi) {
  const auto [min, max] = extent_along<Axis>(polygon);
  if (max < lo || min > hi) {
    polygon.size = 0;
    return;
  }
  if (min < lo) clip<Axis>(polygon, lo, -1.0);
  if (max > hi) clip<Axis>(polygon, hi, 1.0);
}

Polygon polygon_of(const std::array<glm::vec3, 3>& triangle) {
  Polygon polygon;
  for (const glm::vec3& p : triangle) polygon.points[polygon.size++] = glm::dvec3(p);
  return polygon;
}

// The cell's slab along `axis`, moved out by a few float steps of the cell's
// coordinates: far more than the double rounding of the crossings, far less
// than anything a float ray resolves.
std::array<double, 2> slab_of(const Bounds3& cell, int axis) {
  const double margin = 1e-3 * std::numeric_limits<float>::epsilon() *
                        std::max(std::abs(double(cell.lo[axis])), std::abs(double(cell.hi[axis])));
  return {double(cell.lo[axis]) - margin, double(cell.hi[axis]) + margin};
}

template <int Axis>
void clip_to_cell(Polygon& polygon, const Bounds3& cell) {
  if (polygon.size == 0) return;
  const auto [lo, hi] = slab_of(cell, Axis);
  clip_to_slab<Axis>(polygon, lo, hi);
}

// A box in double, grown corner by corner.
struct CornerBox {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};

  void extend(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool is_empty() const { return !(lo.x <= hi.x); }
};

CornerBox box_of(const Polygon& polygon) {
  CornerBox box;
  for (int i = 0; i < polygon.size; ++i) box.extend(polygon.points[i]);
  return box;
}

// The box of what clip<Axis>(polygon, plane, sign) would keep, without
// storing it: the last clip of a part only needs its box.
template <int Axis>
CornerBox box_of_clipped(const Polygon& polygon, double plane, double sign) {
  CornerBox box;
  for_each_clipped_corner<Axis>(polygon, plane, sign, [&](const glm::dvec3& p) { box.extend(p); });
  return box;
}

// The box, rounded outward to float and clamped to the cell.
std::optional<Bounds3> rounded_into(const CornerBox& corners, const Bounds3& cell) {
  if (corners.is_empty()) return std::nullopt;
  // Whole vectors, not one float at a time: a box stored float by float and
  // then read as a vector waits for the stores.
  const auto lo = [&](int axis) { return std::max(round_down(corners.lo[axis]), cell.lo[axis]); };
  const auto hi = [&](int axis) { return std::min(round_up(corners.hi[axis]), cell.hi[axis]); };
  Bounds3 box;
  box.lo = glm::vec3(lo(0), lo(1), lo(2));
  box.hi = glm::vec3(hi(0), hi(1), hi(2));
  return box;
}

// clip_to_cell<Axis> of a copy of `polygon`, then its box rounded into the
// cell, bit for bit, without copying or storing more corners than needed.
template <int Axis>
std::optional<Bounds3> part_in_cell(const Polygon& polygon, const Bounds3& cell) {
  if (polygon.size == 0) return std::nullopt;
  const auto [lo, hi] = slab_of(cell, Axis);
  const auto [min, max] = extent_along<Axis>(polygon);
  if (max < lo || min > hi) return std::nullopt;
  if (min < lo && max > hi) {
    Polygon part = polygon;
    clip<Axis>(part, lo, -1.0);
    return rounded_into(box_of_clipped<Axis>(part, hi, 1.0), cell);
  }
  if (min < lo) return rounded_into(box_of_clipped<Axis>(polygon, lo, -1.0), cell);
  if (max > hi) return rounded_into(box_of_clipped<Axis>(polygon, hi, 1.0), cell);
  return rounded_into(box_of(polygon), cell);
}

// clipped_bounds_of_split along Axis: the walls both cells share (the other
// axes', in increasing order) first.
template <int Axis>
std::array<std::optional<Bounds3>, 2> parts_of_split(const std::array<glm::vec3, 3>& triangle, const Bounds3& below,
                                                     const Bounds3& above) {
  constexpr int kFirstOther = Axis == 0 ? 1 : 0, kSecondOther = Axis == 2 ? 1 : 2;
  Polygon shared = polygon_of(triangle);
  clip_to_cell<kFirstOther>(shared, below);
  clip_to_cell<kSecondOther>(shared, below);
  return {part_in_cell<Axis>(shared, below), part_in_cell<Axis>(shared, above)};
}

}  // namespace

std::optional<Bounds3> clipped_bounds(const std::array<glm::vec3, 3>& triangle, const Bounds3& cell) {
  Polygon polygon = polygon_of(triangle);
  clip_to_cell<0>(polygon, cell);
  clip_to_cell<1>(polygon, cell);
  return part_in_cell<2>(polygon, cell);
}

std::array<std::optional<Bounds3>, 2> clipped_bounds_of_split(const std::array<glm::vec3, 3>& triangle,
                                                              const Bounds3& below, const Bounds3& above, int axis) {
  switch (axis) {
    case 0: return parts_of_split<0>(triangle, below, above);
    case 1: return parts_of_split<1>(triangle, below, above);
    default: return parts_of_split<2>(triangle, below, above);
  }
}

}  // namespace mbao
