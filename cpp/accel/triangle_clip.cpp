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

// Where the edge from a to b, at signed distances da and db from the plane,
// crosses it: exactly on the plane, whatever the rounding of the rest.
glm::dvec3 crossing(const glm::dvec3& a, const glm::dvec3& b, double da, double db, int axis, double plane) {
  glm::dvec3 p = a + (b - a) * (da / (da - db));
  p[axis] = plane;
  return p;
}

// Hands `keep` the corners of the part of `polygon` with
// sign * (p[axis] - plane) <= 0, in order: each corner on that side and where
// each edge crosses the plane. Edges go from a corner to the next (the index
// wraps by a compare, not %, which is a division).
template <class Keep>
void for_each_clipped_corner(const Polygon& polygon, int axis, double plane, double sign, Keep&& keep) {
  for (int i = 0, j = polygon.size > 1 ? 1 : 0; i < polygon.size; ++i, j = j + 1 < polygon.size ? j + 1 : 0) {
    const glm::dvec3& a = polygon.points[i];
    const glm::dvec3& b = polygon.points[j];
    const double da = sign * (a[axis] - plane), db = sign * (b[axis] - plane);
    if (da <= 0.0) keep(a);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) keep(crossing(a, b, da, db, axis, plane));
  }
}

// Keeps the part of `polygon` with sign * (p[axis] - plane) <= 0.
void clip(Polygon& polygon, int axis, double plane, double sign) {
  Polygon in;  // only the corners in use: most polygons have 3 or 4
  in.size = polygon.size;
  std::copy_n(polygon.points.begin(), polygon.size, in.points.begin());
  polygon.size = 0;
  for_each_clipped_corner(in, axis, plane, sign, [&](const glm::dvec3& p) { polygon.points[polygon.size++] = p; });
}

// The least and greatest coordinate of the polygon's corners along `axis`.
std::array<double, 2> extent_along(const Polygon& polygon, int axis) {
  double min = polygon.points[0][axis], max = min;
  for (int i = 1; i < polygon.size; ++i) {
    min = std::min(min, polygon.points[i][axis]);
    max = std::max(max, polygon.points[i][axis]);
  }
  return {min, max};
}

// Clips `polygon` to lo <= p[axis] <= hi. Most triangles a split straddles
// cross only the split plane: planes the polygon does not cross cost nothing.
void clip_to_slab(Polygon& polygon, int axis, double lo, double hi) {
  const auto [min, max] = extent_along(polygon, axis);
  if (max < lo || min > hi) {
    polygon.size = 0;
    return;
  }
  if (min < lo) clip(polygon, axis, lo, -1.0);
  if (max > hi) clip(polygon, axis, hi, 1.0);
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

void clip_to_cell(Polygon& polygon, const Bounds3& cell, int axis) {
  if (polygon.size == 0) return;
  const auto [lo, hi] = slab_of(cell, axis);
  clip_to_slab(polygon, axis, lo, hi);
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

// The box of what clip(polygon, axis, plane, sign) would keep, without
// storing it: the last clip of a part only needs its box.
CornerBox box_of_clipped(const Polygon& polygon, int axis, double plane, double sign) {
  CornerBox box;
  for_each_clipped_corner(polygon, axis, plane, sign, [&](const glm::dvec3& p) { box.extend(p); });
  return box;
}

// The box, rounded outward to float and clamped to the cell.
std::optional<Bounds3> rounded_into(const CornerBox& corners, const Bounds3& cell) {
  if (corners.is_empty()) return std::nullopt;
  Bounds3 box;
  for (int axis = 0; axis < 3; ++axis) {
    box.lo[axis] = std::max(round_down(corners.lo[axis]), cell.lo[axis]);
    box.hi[axis] = std::min(round_up(corners.hi[axis]), cell.hi[axis]);
  }
  return box;
}

// clip_to_cell of a copy of `polygon` along `axis`, then its box rounded into
// the cell, bit for bit, without copying or storing more corners than needed.
std::optional<Bounds3> part_in_cell(const Polygon& polygon, const Bounds3& cell, int axis) {
  if (polygon.size == 0) return std::nullopt;
  const auto [lo, hi] = slab_of(cell, axis);
  const auto [min, max] = extent_along(polygon, axis);
  if (max < lo || min > hi) return std::nullopt;
  if (min < lo && max > hi) {
    Polygon part = polygon;
    clip(part, axis, lo, -1.0);
    return rounded_into(box_of_clipped(part, axis, hi, 1.0), cell);
  }
  if (min < lo) return rounded_into(box_of_clipped(polygon, axis, lo, -1.0), cell);
  if (max > hi) return rounded_into(box_of_clipped(polygon, axis, hi, 1.0), cell);
  return rounded_into(box_of(polygon), cell);
}

}  // namespace

std::optional<Bounds3> clipped_bounds(const std::array<glm::vec3, 3>& triangle, const Bounds3& cell) {
  Polygon polygon = polygon_of(triangle);
  clip_to_cell(polygon, cell, 0);
  clip_to_cell(polygon, cell, 1);
  return part_in_cell(polygon, cell, 2);
}

std::array<std::optional<Bounds3>, 2> clipped_bounds_of_split(const std::array<glm::vec3, 3>& triangle,
                                                              const Bounds3& below, const Bounds3& above,
                                                              int axis) {
  Polygon shared = polygon_of(triangle);
  for (int other = 0; other < 3; ++other)
    if (other != axis) clip_to_cell(shared, below, other);  // the walls both cells share
  return {part_in_cell(shared, below, axis), part_in_cell(shared, above, axis)};
}

}  // namespace mbao
