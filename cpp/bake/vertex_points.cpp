#include "bake/vertex_points.h"

#include <algorithm>
#include <glm/geometric.hpp>

namespace mbao {
namespace {

double triangle_area(const TriangleMesh& mesh, const glm::uvec3& t) {
  const glm::dvec3 p0(mesh.positions[t.x]), p1(mesh.positions[t.y]), p2(mesh.positions[t.z]);
  return 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
}

// The median of three uniform numbers: Beta(2, 2), density 6 x (1 - x).
double median(double a, double b, double c) { return std::max(std::min(a, b), std::min(std::max(a, b), c)); }

}  // namespace

VertexPoints::VertexPoints(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles)
    : ring_start_(mesh.positions.size() + 1, 0) {
  std::vector<std::uint32_t> with_area;
  std::vector<double> areas;
  for (const std::uint32_t t : triangles) {
    const double area = triangle_area(mesh, mesh.triangles.at(t));
    if (!(area > 0.0)) continue;
    with_area.push_back(t);
    areas.push_back(area);
    for (int c = 0; c < 3; ++c) ++ring_start_[mesh.triangles[t][c] + 1];
  }
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) ring_start_[v + 1] += ring_start_[v];
  rings_.resize(ring_start_.back());
  std::vector<std::size_t> filled(ring_start_.begin(), ring_start_.end() - 1);
  for (std::size_t i = 0; i < with_area.size(); ++i) {
    const std::uint32_t t = with_area[i];
    for (std::uint32_t c = 0; c < 3; ++c) {
      const std::uint32_t v = mesh.triangles[t][int(c)];
      const std::size_t slot = filled[v]++;
      const double before = slot == ring_start_[v] ? 0.0 : rings_[slot - 1].area_so_far;
      rings_[slot] = {t, c, before + areas[i]};
    }
  }
}

std::optional<SurfacePoint> VertexPoints::point(std::size_t vertex, const std::array<double, 4>& random) const {
  const auto first = rings_.begin() + std::ptrdiff_t(ring_start_[vertex]);
  const auto last = rings_.begin() + std::ptrdiff_t(ring_start_[vertex + 1]);
  if (first == last) return std::nullopt;
  // A triangle with probability proportional to its area: each holds a third
  // of its area under the hat function. What is left of random[0] shares the rest.
  const auto [chosen, split] = pick_by_area(first, last, random[0]);
  double b[3];
  const std::uint32_t c = chosen->corner;
  b[c] = median(random[1], random[2], random[3]);
  b[(c + 1) % 3] = (1.0 - b[c]) * split;
  b[(c + 2) % 3] = (1.0 - b[c]) * (1.0 - split);
  return SurfacePoint{chosen->triangle, float(b[1]), float(b[2])};
}

}  // namespace mbao
