// The charts of generated UVs (bake/uv_charts.h, SPEC 6.3).
#include "bake/uv_charts.h"

#include <gtest/gtest.h>

#include <glm/vec4.hpp>

namespace {

// A unit cube's surface, outward: eight vertices, two triangles a face.
mbao::TriangleMesh cube() {
  mbao::TriangleMesh mesh;
  for (int v = 0; v < 8; ++v) mesh.positions.emplace_back(v & 1, (v >> 1) & 1, (v >> 2) & 1);
  const glm::uvec4 faces[6] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const glm::uvec4& f : faces) {
    mesh.triangles.emplace_back(f.x, f.y, f.z);
    mesh.triangles.emplace_back(f.x, f.z, f.w);
  }
  return mesh;
}

TEST(UvCharts, ACubeUnfoldsIntoFewConformalChartsWithoutStretch) {
  const mbao::TriangleMesh mesh = cube();
  const mbao::ChartSurface surface = mbao::chart_surface(mesh, mesh.all_triangles());
  const mbao::LaidCharts laid = mbao::conformal_charts(surface, std::vector<int>(mesh.triangles.size(), 0));
  // A closed surface cannot lie flat in one piece, but faces joined across
  // edges, as in a net, lie flat without stretch: halving the cube leaves six
  // pieces, and merging joins some of them, where projecting takes a chart a face.
  EXPECT_LT(laid.members.size(), 6u);
  EXPECT_NEAR(laid.worst_stretch, 1.0, 1e-9);
  std::size_t triangles = 0;
  for (const auto& members : laid.members) triangles += members.size();
  EXPECT_EQ(triangles, mesh.triangles.size());
  EXPECT_EQ(mbao::projected_charts(surface, std::vector<int>(mesh.triangles.size(), 0)).members.size(), 6u);
}

}  // namespace
