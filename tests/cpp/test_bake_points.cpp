// Where a bake's estimates land (SPEC 6.2, 6.3): the distributions the
// estimators assume, checked by their moments within 4 standard errors, and
// the layout's pieces, coverage and claims, exactly.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "bake/dilation.h"
#include "bake/texel_layout.h"
#include "bake/vertex_points.h"

namespace mbao {
namespace {

// Two triangles of a unit square in y = 0: (0,0,0) (1,0,0) (1,0,1) and (0,0,0) (1,0,1) (0,0,1).
TriangleMesh unit_square() {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

double weight_of_vertex(const TriangleMesh& mesh, const SurfacePoint& p, std::uint32_t vertex) {
  const glm::uvec3 t = mesh.triangles[p.triangle];
  const double b[3] = {1.0 - p.b1 - p.b2, p.b1, p.b2};
  for (int k = 0; k < 3; ++k)
    if (t[k] == vertex) return b[k];
  return 0.0;
}

TEST(VertexPoints, DrawsTheRingWithDensityProportionalToTheHatFunction) {
  // phi_v at a point drawn with density proportional to phi_v is Beta(2, 2):
  // mean 1/2, variance 1/20. Vertex 0 has both triangles, vertex 1 one.
  const TriangleMesh mesh = unit_square();
  const VertexPoints points(mesh, mesh.all_triangles());
  ASSERT_EQ(points.targets(), 4u);
  constexpr int n = 200000;
  for (std::uint32_t vertex : {0u, 1u}) {
    double sum = 0.0, sum_of_squares = 0.0;
    int in_first = 0;
    for (int i = 0; i < n; ++i) {
      const SurfacePoint p = *points.point(vertex, estimate_random(vertex, std::uint32_t(i), 7));
      const double phi = weight_of_vertex(mesh, p, vertex);
      sum += phi;
      sum_of_squares += phi * phi;
      in_first += p.triangle == 0;
    }
    EXPECT_NEAR(sum / n, 0.5, 4.0 * std::sqrt(0.05 / n)) << vertex;
    // E[phi^2] = 3/10 with Var[phi^2] = E[phi^4] - 0.09 = 1/7 - 0.09.
    EXPECT_NEAR(sum_of_squares / n, 0.3, 4.0 * std::sqrt((1.0 / 7.0 - 0.09) / n)) << vertex;
    if (vertex == 0) {
      EXPECT_NEAR(double(in_first) / n, 0.5, 4.0 * std::sqrt(0.25 / n));  // equal areas
    } else {
      EXPECT_EQ(in_first, n);
    }
  }
}

TEST(VertexPoints, AVertexWithoutAreaHasNoPoints) {
  TriangleMesh mesh = unit_square();
  mesh.positions.push_back({5, 5, 5});
  mesh.triangles.push_back({4, 4, 0});
  const VertexPoints points(mesh, mesh.all_triangles());
  EXPECT_FALSE(points.point(4, estimate_random(4, 0, 0)));
}

TEST(VertexPoints, DrawOnlyOnTheTrianglesBaked) {
  // Baking triangle 1 alone: vertex 0's ring is that triangle, and vertex 1,
  // which only triangle 0 uses, holds no surface.
  const TriangleMesh mesh = unit_square();
  const VertexPoints points(mesh, {1});
  EXPECT_FALSE(points.has_surface(1));
  EXPECT_FALSE(points.point(1, estimate_random(1, 0, 0)));
  for (std::uint32_t i = 0; i < 1000; ++i) EXPECT_EQ(points.point(0, estimate_random(0, i, 3))->triangle, 1u);
}

TEST(TexelLayout, DrawsEachTexelsSurfaceUniformly) {
  // UVs (x, z) / 2 put the square into the lower-left quarter of a 4 x 4
  // texture: texel (1, 1) holds [0.25, 0.5]^2 of UV, i.e. [0.5, 1]^2 of the
  // square, cut by the diagonal. Points there are uniform: mean (0.75, 0.75).
  const TriangleMesh mesh = unit_square();
  std::vector<glm::vec2> uvs;
  for (const glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) uvs.push_back({mesh.positions[t[k]].x / 2, mesh.positions[t[k]].z / 2});
  const TexelLayout layout(mesh, {0, 1}, uvs, 4, 4, WrapMode::Repeat, WrapMode::Repeat);
  EXPECT_EQ(layout.covered_count(), 4u);
  EXPECT_EQ(layout.claimed_twice(), 0u);
  const std::size_t texel = 1 * 4 + 1;
  ASSERT_TRUE(layout.covered()[texel]);
  constexpr int n = 100000;
  double x = 0.0, z = 0.0;
  for (int i = 0; i < n; ++i) {
    const SurfacePoint p = *layout.point(texel, estimate_random(std::uint32_t(texel), std::uint32_t(i), 3));
    const glm::uvec3 t = mesh.triangles[p.triangle];
    const glm::vec3 q =
        (1.0f - p.b1 - p.b2) * mesh.positions[t.x] + p.b1 * mesh.positions[t.y] + p.b2 * mesh.positions[t.z];
    ASSERT_GE(q.x, 0.5f - 1e-6f);
    ASSERT_GE(q.z, 0.5f - 1e-6f);
    x += q.x;
    z += q.z;
  }
  const double tolerance = 4.0 * std::sqrt(0.25 * 0.25 / 12.0 / n);  // uniform on [0.5, 1]
  EXPECT_NEAR(x / n, 0.75, tolerance);
  EXPECT_NEAR(z / n, 0.75, tolerance);
  EXPECT_FALSE(layout.point(3 * 4 + 3, estimate_random(15, 0, 0)));
}

// Brute force for the layout's coverage and claims (SPEC 6.3): a texel is
// covered where a triangle's UV image clipped to it has positive area, and
// claimed twice where two images hold one of its 4 x 4 sample points.
double area_in_cell(std::vector<glm::dvec2> polygon, double x, double y) {
  const auto clip = [&](int axis, double bound, double keep) {  // keep: +1 above the bound, -1 below
    std::vector<glm::dvec2> out;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
      const double da = keep * (a[axis] - bound), db = keep * (b[axis] - bound);
      if (da >= 0.0) out.push_back(a);
      if ((da < 0.0) != (db < 0.0)) out.push_back(a + (b - a) * (da / (da - db)));
    }
    polygon = out;
  };
  clip(0, x, 1.0);
  clip(0, x + 1.0, -1.0);
  clip(1, y, 1.0);
  clip(1, y + 1.0, -1.0);
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * std::abs(twice);
}

bool holds_point(const std::array<glm::dvec2, 3>& t, glm::dvec2 p) {
  double sides[3];
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
    sides[k] = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
  }
  return (sides[0] > 0.0 && sides[1] > 0.0 && sides[2] > 0.0) || (sides[0] < 0.0 && sides[1] < 0.0 && sides[2] < 0.0);
}

TEST(TexelLayout, CoversAndClaimsWhatClippingAndPointTestsGive) {
  // Overlapping triangles from a texel's size to a quarter of a 64 x 64
  // texture at random, so that most texels of the large ones lie wholly inside
  // or outside them, and a few dozen points fall on no edge's rounding.
  constexpr int kSide = 64, kTriangles = 60;
  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(0.02f, 0.98f), offset(-0.4f, 0.4f);
  TriangleMesh mesh;
  std::vector<std::uint32_t> triangles;
  std::vector<glm::vec2> uvs;
  std::vector<std::array<glm::dvec2, 3>> texels_of;  // each triangle's UVs in texels
  for (std::uint32_t t = 0; t < kTriangles; ++t) {
    const float size = t % 3 == 0 ? 0.02f : 1.0f;
    const glm::vec2 centre(uniform(random), uniform(random));
    std::array<glm::dvec2, 3> corners;
    for (int k = 0; k < 3; ++k) {
      const glm::vec2 uv = glm::clamp(centre + size * glm::vec2(offset(random), offset(random)), 0.0f, 0.999f);
      uvs.push_back(uv);
      corners[std::size_t(k)] = glm::dvec2(uv) * double(kSide);
      mesh.positions.push_back({uv.x, float(k), uv.y});
    }
    mesh.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    triangles.push_back(t);
    texels_of.push_back(corners);
  }
  const TexelLayout layout(mesh, triangles, uvs, kSide, kSide, WrapMode::Repeat, WrapMode::Repeat);

  std::vector<std::uint8_t> covered(kSide * kSide, 0);
  std::vector<std::uint16_t> once(kSide * kSide, 0), twice(kSide * kSide, 0);
  std::vector<std::size_t> second_claimants;
  for (std::size_t t = 0; t < texels_of.size(); ++t) {
    const std::vector<glm::dvec2> image(texels_of[t].begin(), texels_of[t].end());
    bool again = false;
    for (int y = 0; y < kSide; ++y)
      for (int x = 0; x < kSide; ++x) {
        const std::size_t texel = std::size_t(y * kSide + x);
        covered[texel] |= area_in_cell(image, x, y) > 0.0;
        std::uint16_t claimed = 0;
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i)
            if (holds_point(texels_of[t], {x + (i + 0.5 + 1e-3) / 4, y + (j + 0.5 + 1e-3) / 4}))
              claimed |= std::uint16_t(1u << (4 * j + i));
        twice[texel] |= once[texel] & claimed;
        again = again || (once[texel] & claimed) != 0;
        once[texel] |= claimed;
      }
    if (again) second_claimants.push_back(t);
  }
  std::size_t claimed_twice = 0;
  for (std::size_t texel = 0; texel < covered.size(); ++texel) claimed_twice += covered[texel] && twice[texel];
  EXPECT_EQ(layout.covered(), covered);
  EXPECT_EQ(layout.claimed_twice(), claimed_twice);
  EXPECT_EQ(layout.second_claimants(), second_claimants);
  EXPECT_GT(claimed_twice, 100u);  // the triangles overlap
}

TEST(TexelLayout, RefusesUvsThatAreNotFinite) {
  const TriangleMesh mesh = unit_square();
  std::vector<glm::vec2> uvs(6, {0.5f, 0.5f});
  uvs[4].x = std::nanf("");
  EXPECT_THROW(TexelLayout(mesh, {0, 1}, uvs, 4, 4, WrapMode::Repeat, WrapMode::Repeat), std::invalid_argument);
}

TEST(Dilation, TakesTheNearestCoveredTexelWithinThePadding) {
  // One row: covered texels 2 (value 0.2) and 6 (0.6); padding 2.
  const std::vector<std::uint8_t> covered = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  std::vector<float> values = {1, 1, 0.2f, 1, 1, 1, 0.6f, 1, 1, 1};
  const std::vector<std::uint8_t> filled = dilate(covered, 10, 1, 2, {&values});
  const std::vector<float> expected = {0.2f, 0.2f, 0.2f, 0.2f, 0.2f, 0.6f, 0.6f, 0.6f, 0.6f, 1};
  EXPECT_EQ(values, expected);  // texel 4 is 2 from both: the first in row order wins
  EXPECT_EQ(filled, (std::vector<std::uint8_t>{1, 1, 0, 1, 1, 1, 0, 1, 1, 0}));
}

}  // namespace
}  // namespace mbao
