// The charts of generated UVs (bake/uv_charts.h, SPEC 6.3).
#include "bake/uv_charts.h"

#include <algorithm>

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

// A floor of `columns` x `rows` unit squares in the plane z = 0, each of two
// triangles split along its rising diagonal: first the one below it (its
// bottom and right edges), then the one above (its top and left edges).
mbao::TriangleMesh floor_of_squares(int columns, int rows) {
  mbao::TriangleMesh mesh;
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i <= columns; ++i) mesh.positions.emplace_back(i, j, 0);
  const auto vertex = [&](int i, int j) { return std::uint32_t(j * (columns + 1) + i); };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i) {
      mesh.triangles.emplace_back(vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1));
      mesh.triangles.emplace_back(vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1));
    }
  return mesh;
}

// Each piece's triangles in ascending order.
std::vector<std::vector<std::uint32_t>> sorted(std::vector<std::vector<std::uint32_t>> pieces) {
  for (std::vector<std::uint32_t>& piece : pieces) std::sort(piece.begin(), piece.end());
  return pieces;
}

TEST(UvCharts, AJaggedCutIsShortenedToAStraightOne) {
  // Cut at y = 1.5 by centroids, the middle row's triangles part along their
  // diagonals: each one below its diagonal shares a bottom edge with the
  // lower piece, and its diagonal and right edge with the upper, so it moves
  // up, and the cut runs straight along y = 1.
  const int columns = 6;
  const mbao::TriangleMesh mesh = floor_of_squares(columns, 3);
  const mbao::ChartSurface surface = mbao::chart_surface(mesh, mesh.all_triangles());
  std::vector<std::vector<std::uint32_t>> by_centroid(2), row_0_and_above(2);
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const double centroid_y =
        (surface.corners[3 * t].y + surface.corners[3 * t + 1].y + surface.corners[3 * t + 2].y) / 3.0;
    by_centroid[centroid_y < 1.5 ? 0 : 1].push_back(t);
    row_0_and_above[t < 2 * columns ? 0 : 1].push_back(t);
  }
  ASSERT_EQ(by_centroid[0].size(), 3u * columns);  // the jagged cut: row 0, and the middle row's lower triangles
  EXPECT_EQ(sorted(mbao::shortened_cuts(by_centroid, surface)), row_0_and_above);
}

TEST(UvCharts, ShorteningACutLeavesEveryPieceATriangle) {
  // A triangle alone in its piece shares its whole boundary with the other,
  // but stays: a piece never empties, so halving always makes two.
  const mbao::TriangleMesh mesh = floor_of_squares(3, 3);
  const mbao::ChartSurface surface = mbao::chart_surface(mesh, mesh.all_triangles());
  const std::uint32_t middle = 8;  // below the middle square's diagonal
  std::vector<std::vector<std::uint32_t>> pieces(2);
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) pieces[t == middle ? 1 : 0].push_back(t);
  EXPECT_EQ(mbao::shortened_cuts(pieces, surface), pieces);
}

TEST(UvCharts, ACutCreepsAlongARibbonUntilTheRibbonStopsNarrowing) {
  // A ribbon of triangles, alternately up and down, between a straight bottom
  // edge and a top one whose height is 1 up to x = 5.3 and rises by 1 a step
  // after it; neighbours share a rung from bottom to top. Cut far to the
  // right, the cut moves a triangle at a time, each move onto a shorter rung,
  // until the ribbon stops narrowing: the rungs on either side of triangle 9,
  // from bottom vertex 5, are 1.22 and 1.04 long.
  const int steps = 12;
  mbao::TriangleMesh mesh;
  for (int k = 0; k <= steps; ++k) {
    mesh.positions.emplace_back(k, 0, 0);                               // vertex 2k, bottom
    mesh.positions.emplace_back(k + 0.3, 1.0 + std::max(0, k - 5), 0);  // vertex 2k + 1, top
  }
  for (std::uint32_t k = 0; k < steps; ++k) {
    mesh.triangles.emplace_back(2 * k, 2 * k + 2, 2 * k + 1);      // triangle 2k, up
    mesh.triangles.emplace_back(2 * k + 2, 2 * k + 3, 2 * k + 1);  // triangle 2k + 1, down
  }
  const mbao::ChartSurface surface = mbao::chart_surface(mesh, mesh.all_triangles());
  std::vector<std::vector<std::uint32_t>> far_right(2), where_it_stops_narrowing(2);
  for (std::uint32_t t = 0; t < 2 * steps; ++t) {
    far_right[t < 20 ? 0 : 1].push_back(t);
    where_it_stops_narrowing[t <= 9 ? 0 : 1].push_back(t);
  }
  EXPECT_EQ(sorted(mbao::shortened_cuts(far_right, surface)), where_it_stops_narrowing);
}

}  // namespace
