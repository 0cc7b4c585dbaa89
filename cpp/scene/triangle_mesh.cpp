#include "scene/triangle_mesh.h"

#include <cmath>
#include <numeric>
#include <stdexcept>

namespace mbao {
namespace {

bool is_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

std::vector<std::uint32_t> TriangleMesh::all_triangles() const {
  std::vector<std::uint32_t> all(triangles.size());
  std::iota(all.begin(), all.end(), 0u);
  return all;
}

Bounds3 TriangleMesh::bounds() const {
  Bounds3 box;
  for (const glm::uvec3& t : triangles)
    for (int k = 0; k < 3; ++k) box.extend(positions[t[k]]);
  return box;
}

Bounds3 TriangleMesh::checked_bounds(const std::string& what) const {
  if (triangles.empty()) throw std::invalid_argument(what + " has no triangles");
  if (!normals.empty() && normals.size() != positions.size())
    throw std::invalid_argument(what + " has " + std::to_string(normals.size()) + " normals for " +
                                std::to_string(positions.size()) + " vertices");
  for (size_t i = 0; i < positions.size(); ++i)
    if (!is_finite(positions[i]))
      throw std::invalid_argument(what + ": vertex " + std::to_string(i) + " is not finite");
  for (size_t i = 0; i < normals.size(); ++i)
    if (!is_finite(normals[i])) throw std::invalid_argument(what + ": normal " + std::to_string(i) + " is not finite");
  Bounds3 box;
  for (size_t i = 0; i < triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      if (triangles[i][k] >= positions.size())
        throw std::invalid_argument(what + ": triangle " + std::to_string(i) + " uses vertex " +
                                    std::to_string(triangles[i][k]) + ", but there are only " +
                                    std::to_string(positions.size()) + " vertices");
      box.extend(positions[triangles[i][k]]);
    }
  return box;
}

}  // namespace mbao
