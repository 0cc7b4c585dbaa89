#include "accel/triangle_clip.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <limits>

namespace mbao {
namespace {

// A convex polygon: the triangle, cut by at most 6 planes, has at most 9 corners.
struct Polygon {
  std::array<glm::dvec3, 9> points;
  int size = 0;
};

// Keeps the part of `in` with sign * (p[axis] - plane) <= 0.
Polygon clip(const Polygon& in, int axis, double plane, double sign) {
  Polygon out;
  for (int i = 0; i < in.size; ++i) {
    const glm::dvec3& a = in.points[i];
    const glm::dvec3& b = in.points[(i + 1) % in.size];
    const double da = sign * (a[axis] - plane), db = sign * (b[axis] - plane);
    if (da <= 0.0) out.points[out.size++] = a;
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
      glm::dvec3 crossing = a + (b - a) * (da / (da - db));
      crossing[axis] = plane;  // exactly on the plane, whatever the rounding above
      out.points[out.size++] = crossing;
    }
  }
  return out;
}

float round_down(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

float round_up(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

}  // namespace

std::optional<Bounds3> clipped_bounds(const std::array<glm::vec3, 3>& triangle, const Bounds3& cell) {
  Polygon polygon;
  for (const glm::vec3& p : triangle) polygon.points[polygon.size++] = glm::dvec3(p);
  for (int axis = 0; axis < 3 && polygon.size > 0; ++axis) {
    // A few float steps of the cell's coordinates: far more than the double
    // rounding of the crossings, far less than anything a float ray resolves.
    const double margin = 1e-3 * std::numeric_limits<float>::epsilon() *
                          std::max(std::abs(double(cell.lo[axis])), std::abs(double(cell.hi[axis])));
    polygon = clip(polygon, axis, double(cell.lo[axis]) - margin, -1.0);
    polygon = clip(polygon, axis, double(cell.hi[axis]) + margin, 1.0);
  }
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

}  // namespace mbao
