#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "scene/bounds.h"

namespace mbao {

// Triangles in world space: what every loader produces. The kd-tree and the
// device get them relative to Scene::render_origin, near the scene.
struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;  // indices into positions
  // Empty, or one per position; a zero vector marks a vertex without a normal.
  std::vector<glm::vec3> normals;

  bool has_normals() const { return !normals.empty(); }
  // The box around the vertices the triangles use.
  Bounds3 bounds() const;
  // bounds(), for a mesh the renderer can use; else throws std::invalid_argument
  // naming `what` and the offending element: no triangles, an index out of
  // range, a non-finite vertex position or normal, a normals array of the wrong length.
  Bounds3 checked_bounds(const std::string& what) const;
  // 0, 1, ..., triangles.size() - 1: every triangle, where a list of them is asked for.
  std::vector<std::uint32_t> all_triangles() const;
};

}  // namespace mbao
