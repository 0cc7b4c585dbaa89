// The conformal maps that lay generated UV charts flat (bake/conformal_map.h, SPEC 6.3).
#include "bake/conformal_map.h"

#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

namespace {

// A grid of `columns` x `rows` quads, two triangles each, at the points `at(i, j)`; vertex ids i + (columns + 1) j.
template <typename At>
void grid(int columns, int rows, At at, std::vector<glm::dvec3>* corners, std::vector<std::uint32_t>* ids) {
  const auto id = [&](int i, int j) { return std::uint32_t(i + (columns + 1) * j); };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i)
      for (const glm::ivec2 corner : {glm::ivec2(0, 0), glm::ivec2(1, 0), glm::ivec2(1, 1), glm::ivec2(0, 0),
                                      glm::ivec2(1, 1), glm::ivec2(0, 1)}) {
        corners->push_back(at(i + corner.x, j + corner.y));
        ids->push_back(id(i + corner.x, j + corner.y));
      }
}

// Each triangle's edge lengths in the map over those on the surface: 1 where the map keeps lengths.
std::vector<double> length_ratios(const std::vector<glm::dvec3>& corners, const mbao::ConformalChart& chart) {
  std::vector<double> ratios;
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const std::size_t next = c - c % 3 + (c + 1) % 3;
    ratios.push_back(glm::distance(chart.corners[c], chart.corners[next]) / glm::distance(corners[c], corners[next]));
  }
  return ratios;
}

TEST(ConformalMap, ATiltedPlaneLiesFlatWithItsLengthsKept) {
  std::vector<glm::dvec3> corners;
  std::vector<std::uint32_t> ids;
  const glm::dvec3 u = glm::normalize(glm::dvec3(1, 2, 3)), v = glm::normalize(glm::cross(u, glm::dvec3(0, 0, 1)));
  grid(
      4, 3, [&](int i, int j) { return 0.7 * i * u + 1.3 * j * v; }, &corners, &ids);
  const std::optional<mbao::ConformalChart> chart = mbao::conformal_map(corners, ids, 1.25);
  ASSERT_TRUE(chart.has_value());
  EXPECT_NEAR(chart->stretch, 1.0, 1e-9);
  for (double ratio : length_ratios(corners, *chart)) EXPECT_NEAR(ratio, 1.0, 1e-9);
  EXPECT_TRUE(chart->overlapping.empty());
}

TEST(ConformalMap, TrianglesSharingAVertexShareItsPlace) {
  std::vector<glm::dvec3> corners;
  std::vector<std::uint32_t> ids;
  grid(
      3, 3, [](int i, int j) { return glm::dvec3(i, j, 0.1 * i * j); }, &corners, &ids);
  const std::optional<mbao::ConformalChart> chart = mbao::conformal_map(corners, ids, 2.0);
  ASSERT_TRUE(chart.has_value());
  for (std::size_t a = 0; a < ids.size(); ++a)
    for (std::size_t b = 0; b < ids.size(); ++b)
      if (ids[a] == ids[b]) {
        EXPECT_EQ(chart->corners[a], chart->corners[b]);
      }
}

// A quarter of a cylinder's side unrolls onto the plane: no stretch, where projecting it would squeeze its
// rim by cos 45 degrees.
TEST(ConformalMap, ACylindersSideUnrollsWithoutStretch) {
  std::vector<glm::dvec3> corners;
  std::vector<std::uint32_t> ids;
  const int around = 12;
  grid(
      around, 4,
      [&](int i, int j) {
        const double angle = 0.5 * M_PI * i / around - 0.25 * M_PI;
        return glm::dvec3(std::sin(angle), std::cos(angle), 0.5 * j);
      },
      &corners, &ids);
  const std::optional<mbao::ConformalChart> chart = mbao::conformal_map(corners, ids, 1.25);
  ASSERT_TRUE(chart.has_value());
  EXPECT_NEAR(chart->stretch, 1.0, 1e-9);
  for (double ratio : length_ratios(corners, *chart)) EXPECT_NEAR(ratio, 1.0, 1e-9);
}

// A sphere's cap cannot lie flat without stretch: one reaching 17 degrees from its pole (along its grid's
// axes) lies within the bound, one reaching 80 degrees beyond it.
TEST(ConformalMap, ASpheresCapStretchesMoreTheWiderItIs) {
  const auto cap = [](double widest, std::vector<glm::dvec3>* corners, std::vector<std::uint32_t>* ids) {
    grid(
        16, 16,
        [&](int i, int j) {
          const double x = widest * (i / 8.0 - 1.0), y = widest * (j / 8.0 - 1.0);  // angles from the pole
          return glm::normalize(glm::dvec3(std::tan(x), std::tan(y), 1.0));
        },
        corners, ids);
  };
  std::vector<glm::dvec3> narrow, wide;
  std::vector<std::uint32_t> narrow_ids, wide_ids;
  cap(0.3, &narrow, &narrow_ids);
  cap(1.4, &wide, &wide_ids);
  const std::optional<mbao::ConformalChart> chart = mbao::conformal_map(narrow, narrow_ids, 1.25);
  ASSERT_TRUE(chart.has_value());
  EXPECT_GT(chart->stretch, 1.0 + 1e-3);
  EXPECT_LE(chart->stretch, 1.25);
  for (double ratio : length_ratios(narrow, *chart)) EXPECT_TRUE(ratio >= 1.0 / 1.25 && ratio <= 1.25) << ratio;
  EXPECT_FALSE(mbao::conformal_map(wide, wide_ids, 1.25).has_value());
  EXPECT_TRUE(mbao::conformal_map(wide, wide_ids, 4.0).has_value());
}

TEST(ConformalMap, ATriangleThatCoversAnotherIsNamed) {
  std::vector<glm::dvec3> corners;
  std::vector<std::uint32_t> ids;
  grid(
      2, 1, [](int i, int j) { return glm::dvec3(i, j, 0.0); }, &corners, &ids);
  for (int k = 0; k < 3; ++k) {  // the first triangle again
    corners.push_back(corners[k]);
    ids.push_back(ids[k]);
  }
  const std::optional<mbao::ConformalChart> chart = mbao::conformal_map(corners, ids, 1.25);
  ASSERT_TRUE(chart.has_value());
  EXPECT_EQ(chart->overlapping, std::vector<std::uint32_t>{4});
}

}  // namespace
