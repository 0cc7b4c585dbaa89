#pragma once

#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <limits>

namespace mbao {

// An axis-aligned box; default-constructed empty, so extending it by the first
// point makes it that point.
struct Bounds3 {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};

  void extend(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  glm::vec3 extent() const { return hi - lo; }
  glm::vec3 center() const { return 0.5f * (lo + hi); }
  double surface_area() const {
    const glm::dvec3 e = glm::dvec3(hi) - glm::dvec3(lo);
    return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

}  // namespace mbao
