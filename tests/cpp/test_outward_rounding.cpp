// round_down and round_up are the float next to a double on its side: what
// std::nextafter gives from the nearest float when that float missed it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/outward_rounding.h"

namespace mbao {
namespace {

float reference_down(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

float reference_up(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

std::uint32_t bits_of(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

void expect_matches_reference(double x) {
  EXPECT_EQ(bits_of(round_down(x)), bits_of(reference_down(x))) << "x = " << x;
  EXPECT_EQ(bits_of(round_up(x)), bits_of(reference_up(x))) << "x = " << x;
  EXPECT_LE(double(round_down(x)), x);
  EXPECT_GE(double(round_up(x)), x);
}

TEST(OutwardRounding, EdgeCasesAreTheNextFloatOnTheirSide) {
  const double tiny = std::numeric_limits<double>::denorm_min();
  const double float_max = std::numeric_limits<float>::max();
  const double float_denorm = std::numeric_limits<float>::denorm_min();
  std::vector<double> cases = {0.0,
                               -0.0,
                               tiny,
                               -tiny,
                               1e-300,
                               -1e-300,
                               float_denorm,
                               -float_denorm,
                               float_denorm / 3,
                               -float_denorm / 3,
                               1.0,
                               -1.0,
                               1.0 + 1e-12,
                               -1.0 - 1e-12,
                               0.1,
                               -0.1,
                               float_max,
                               -float_max,
                               float_max * 1.0000001,
                               -float_max * 1.0000001,
                               1e300,
                               -1e300,
                               std::numeric_limits<double>::infinity(),
                               -std::numeric_limits<double>::infinity()};
  for (double x : cases) expect_matches_reference(x);
  // Through zero: the smallest denormal of the direction's sign.
  EXPECT_EQ(round_down(-1e-300), -std::numeric_limits<float>::denorm_min());
  EXPECT_EQ(round_up(1e-300), std::numeric_limits<float>::denorm_min());
  EXPECT_EQ(round_up(-1e-300), 0.0f);
  EXPECT_EQ(round_down(1e-300), 0.0f);
}

TEST(OutwardRounding, RandomDoublesMatchNextafter) {
  std::mt19937_64 random(11);
  std::uniform_int_distribution<std::uint64_t> any_bits;
  std::uniform_real_distribution<double> unit(-2.0, 2.0);
  for (int i = 0; i < 200000; ++i) {
    // Doubles of every magnitude (NaNs skipped), and near-floats in [-2, 2].
    std::uint64_t b = any_bits(random);
    double x;
    std::memcpy(&x, &b, sizeof x);
    if (!std::isnan(x)) expect_matches_reference(x);
    expect_matches_reference(unit(random));
    expect_matches_reference(double(float(unit(random))));
  }
}

}  // namespace
}  // namespace mbao
