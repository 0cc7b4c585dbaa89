// Clipping a triangle to a kd-tree cell ("perfect splits"): the box of its
// part inside the cell, and the children's boxes when a split cuts the cell.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "accel/triangle_clip.h"

namespace mbao {
namespace {

TEST(TriangleClip, BoxOfThePartInsideTheCell) {
  Bounds3 cell;
  cell.extend({0, 0, 0});
  cell.extend({1, 1, 1});
  // Inside: its own box.
  const auto inside = clipped_bounds({{{0.1f, 0.2f, 0.3f}, {0.9f, 0.2f, 0.3f}, {0.1f, 0.8f, 0.5f}}}, cell);
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->lo, glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(inside->hi, glm::vec3(0.9f, 0.8f, 0.5f));
  // Half out along x: the box stops at the wall; y shrinks with the cut edge.
  const auto cut = clipped_bounds({{{0.5f, 0.0f, 0.5f}, {1.5f, 0.0f, 0.5f}, {0.5f, 1.0f, 0.5f}}}, cell);
  ASSERT_TRUE(cut);
  EXPECT_EQ(cut->lo, glm::vec3(0.5f, 0.0f, 0.5f));
  EXPECT_EQ(cut->hi.x, 1.0f);
  EXPECT_NEAR(cut->hi.y, 1.0f, 1e-6f);
  // A diagonal triangle whose box overlaps the cell's corner but which passes by it.
  EXPECT_FALSE(clipped_bounds({{{1.2f, 2.0f, 0.5f}, {2.0f, 1.2f, 0.5f}, {2.0f, 2.0f, 0.5f}}}, cell));
  EXPECT_FALSE(clipped_bounds({{{1.5f, -1.0f, 0.5f}, {1.5f, 3.0f, 0.5f}, {3.0f, 1.0f, 0.5f}}}, cell));
  // Touching the cell in one corner only: kept, as a point.
  const auto corner = clipped_bounds({{{1.0f, 1.0f, 1.0f}, {2.0f, 1.0f, 1.0f}, {1.0f, 2.0f, 1.0f}}}, cell);
  ASSERT_TRUE(corner);
  EXPECT_EQ(corner->lo, glm::vec3(1.0f));
  EXPECT_EQ(corner->hi, glm::vec3(1.0f));
}

// The build clips a straddling triangle to the walls its two children share
// once, then to the split plane for each: the boxes are those of clipping to
// each child on its own (to a float step: the crossings round in another
// order), and hold every point of the triangle in the child's cell.
TEST(TriangleClip, SplitCellGivesEachChildsBox) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-0.5f, 1.5f), plane(0.05f, 0.95f);
  std::uniform_real_distribution<double> weight(0.0, 1.0);
  const auto within_a_step = [](float a, float b) { return a == b || std::nextafter(a, b) == b; };
  int split_triangles = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const std::array<glm::vec3, 3> triangle = {glm::vec3(coordinate(random), coordinate(random), coordinate(random)),
                                               glm::vec3(coordinate(random), coordinate(random), coordinate(random)),
                                               glm::vec3(coordinate(random), coordinate(random), coordinate(random))};
    Bounds3 cell;
    cell.extend(glm::vec3(0.0f));
    cell.extend(glm::vec3(1.0f));
    const int axis = trial % 3;
    Bounds3 below = cell, above = cell;
    below.hi[axis] = above.lo[axis] = plane(random);
    const auto parts = clipped_bounds_of_split(triangle, below, above, axis);
    const Bounds3 children[2] = {below, above};
    for (int side = 0; side < 2; ++side) {
      const auto alone = clipped_bounds(triangle, children[side]);
      ASSERT_EQ(bool(parts[side]), bool(alone)) << "trial " << trial << " side " << side;
      if (!alone) continue;
      for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(within_a_step(parts[side]->lo[k], alone->lo[k])) << "trial " << trial;
        EXPECT_TRUE(within_a_step(parts[side]->hi[k], alone->hi[k])) << "trial " << trial;
      }
      for (int sample = 0; sample < 50; ++sample) {
        double u = weight(random), v = weight(random);
        if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
        const glm::dvec3 p = glm::dvec3(triangle[0]) + u * (glm::dvec3(triangle[1]) - glm::dvec3(triangle[0])) +
                             v * (glm::dvec3(triangle[2]) - glm::dvec3(triangle[0]));
        bool in_cell = true, in_box = true;
        for (int k = 0; k < 3; ++k) {
          in_cell &= p[k] >= children[side].lo[k] && p[k] <= children[side].hi[k];
          in_box &= p[k] >= parts[side]->lo[k] && p[k] <= parts[side]->hi[k];
        }
        EXPECT_TRUE(!in_cell || in_box) << "trial " << trial << " side " << side;
      }
    }
    split_triangles += parts[0] && parts[1];
  }
  EXPECT_GT(split_triangles, 200);  // the trials do exercise the split plane
}

}  // namespace
}  // namespace mbao
