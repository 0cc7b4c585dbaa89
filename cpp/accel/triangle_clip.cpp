#include "accel/triangle_clip.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/common.hpp>
#include <limits>

namespace mbao {
namespace {

// A convex polygon: the triangle, cut by at most 6 planes, has at most 9 corners.
struct Polygon {
  std::array<glm::dvec3, 9> points;
  int size = 0;
};

// Keeps the part of `polygon` with sign * (p[axis] - plane) <= 0.
void clip(Polygon& polygon, int axis, double plane, double sign) {
  Polygon in;  // only the corners in use: most polygons have 3 or 4
  in.size = polygon.size;
  std::copy_n(polygon.points.begin(), polygon.size, in.points.begin());
  polygon.size = 0;
  for (int i = 0; i < in.size; ++i) {
    const glm::dvec3& a = in.points[i];
    const glm::dvec3& b = in.points[(i + 1) % in.size];
    const double da = sign * (a[axis] - plane), db = sign * (b[axis] - plane);
    if (da <= 0.0) polygon.points[polygon.size++] = a;
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
      glm::dvec3 crossing = a + (b - a) * (da / (da - db));
      crossing[axis] = plane;  // exactly on the plane, whatever the rounding above
      polygon.points[polygon.size++] = crossing;
    }
  }
}

// Clips `polygon` to lo <= p[axis] <= hi. Most triangles a split straddles
// cross only the split plane: planes the polygon does not cross cost nothing.
void clip_to_slab(Polygon& polygon, int axis, double lo, double hi) {
  double min = polygon.points[0][axis], max = min;
  for (int i = 1; i < polygon.size; ++i) {
    min = std::min(min, polygon.points[i][axis]);
    max = std::max(max, polygon.points[i][axis]);
  }
  if (max < lo || min > hi) {
    polygon.size = 0;
    return;
  }
  if (min < lo) clip(polygon, axis, lo, -1.0);
  if (max > hi) clip(polygon, axis, hi, 1.0);
}

// The next float toward -infinity (direction -1) or +infinity (+1), from a
// float that is not NaN and not already the infinity it steps toward, as
// std::nextafter, which is a library call: the build rounds millions of corners.
float float_step(float f, int direction) {
  if (f == 0.0f) return float(direction) * std::numeric_limits<float>::denorm_min();
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  // Away from zero adds one to the magnitude's bits, toward zero takes one.
  bits = (f > 0.0f) == (direction > 0) ? bits + 1u : bits - 1u;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

float round_down(double x) {
  const float f = float(x);
  return double(f) > x ? float_step(f, -1) : f;
}

float round_up(double x) {
  const float f = float(x);
  return double(f) < x ? float_step(f, +1) : f;
}

Polygon polygon_of(const std::array<glm::vec3, 3>& triangle) {
  Polygon polygon;
  for (const glm::vec3& p : triangle) polygon.points[polygon.size++] = glm::dvec3(p);
  return polygon;
}

// Clips `polygon` to the cell's slab along `axis`, moved out by a few float
// steps of the cell's coordinates: far more than the double rounding of the
// crossings, far less than anything a float ray resolves.
void clip_to_cell(Polygon& polygon, const Bounds3& cell, int axis) {
  if (polygon.size == 0) return;
  const double margin = 1e-3 * std::numeric_limits<float>::epsilon() *
                        std::max(std::abs(double(cell.lo[axis])), std::abs(double(cell.hi[axis])));
  clip_to_slab(polygon, axis, double(cell.lo[axis]) - margin, double(cell.hi[axis]) + margin);
}

// The polygon's box, rounded outward to float and clamped to the cell.
std::optional<Bounds3> bounds_in_cell(const Polygon& polygon, const Bounds3& cell) {
  if (polygon.size == 0) return std::nullopt;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (int i = 0; i < polygon.size; ++i) {
    lo = glm::min(lo, polygon.points[i]);
    hi = glm::max(hi, polygon.points[i]);
  }
  Bounds3 box;
  for (int axis = 0; axis < 3; ++axis) {
    box.lo[axis] = std::max(round_down(lo[axis]), cell.lo[axis]);
    box.hi[axis] = std::min(round_up(hi[axis]), cell.hi[axis]);
  }
  return box;
}

}  // namespace

std::optional<Bounds3> clipped_bounds(const std::array<glm::vec3, 3>& triangle, const Bounds3& cell) {
  Polygon polygon = polygon_of(triangle);
  for (int axis = 0; axis < 3; ++axis) clip_to_cell(polygon, cell, axis);
  return bounds_in_cell(polygon, cell);
}

std::array<std::optional<Bounds3>, 2> clipped_bounds_of_split(const std::array<glm::vec3, 3>& triangle,
                                                              const Bounds3& below, const Bounds3& above,
                                                              int axis) {
  Polygon below_part = polygon_of(triangle);
  for (int other = 0; other < 3; ++other)
    if (other != axis) clip_to_cell(below_part, below, other);  // the walls both cells share
  Polygon above_part = below_part;
  clip_to_cell(below_part, below, axis);
  clip_to_cell(above_part, above, axis);
  return {bounds_in_cell(below_part, below), bounds_in_cell(above_part, above)};
}

}  // namespace mbao
