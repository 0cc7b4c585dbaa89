// Random triangle soups for the kd-tree tests.
#pragma once

#include <cmath>
#include <cstddef>
#include <random>

#include "scene/triangle_mesh.h"

namespace mbao {

// n triangles in the unit cube, mostly small, some large; the same for a seed.
inline TriangleMesh random_soup(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  TriangleMesh mesh;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 center(unit(rng), unit(rng), unit(rng));
    const float size = 0.3f * std::pow(unit(rng), 3.0f);  // mostly small, some large
    for (int k = 0; k < 3; ++k)
      mesh.positions.push_back(center + size * glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f));
    const auto base = std::uint32_t(3 * i);
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

}  // namespace mbao
