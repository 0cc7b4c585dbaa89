// The points of a per-vertex bake (SPEC 6.2): vertex i's estimates are drawn
// over its one-ring, of the triangles baked, with density proportional to its
// hat function.
#pragma once

#include <vector>

#include "bake/estimate_points.h"
#include "scene/triangle_mesh.h"

namespace mbao {

class VertexPoints : public EstimatePoints {
 public:
  // triangles: the ones baked, indices into mesh.triangles (each in range); the rest only occlude.
  VertexPoints(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles);

  std::size_t targets() const override { return ring_start_.size() - 1; }
  bool has_surface(std::size_t vertex) const override { return ring_start_[vertex + 1] > ring_start_[vertex]; }
  std::optional<SurfacePoint> point(std::size_t vertex, const std::array<double, 4>& random) const override;

 private:
  // One triangle of a vertex's ring: which triangle, which of its corners the
  // vertex is, and the ring's area up to and including it.
  struct RingTriangle {
    std::uint32_t triangle;
    std::uint32_t corner;
    double area_so_far;
  };
  std::vector<std::size_t> ring_start_;  // vertex i's ring: rings_[ring_start_[i], ring_start_[i + 1])
  std::vector<RingTriangle> rings_;      // triangles of zero area left out
};

}  // namespace mbao
