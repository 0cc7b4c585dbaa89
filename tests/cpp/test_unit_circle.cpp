// HBAO's directions (kernels/mbao/unit_circle.h): within the stated 5e-7 of
// double precision's cos and sin over the whole circle, on the host and on
// the device.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "device_outputs.h"
#include "mbao/unit_circle.h"
#include "opencl/kernel_sources.h"

namespace mbao {
namespace {

constexpr int kAngles = 1 << 20;
constexpr float kBound = 5e-7f;

float angle_at(int i) { return float(2.0 * M_PI * double(i) / double(kAngles)); }

TEST(UnitCircle, IsWithinItsBoundOfDoublePrecisionOverTheCircle) {
  double worst = 0.0;
  for (int i = 0; i <= kAngles; ++i) {
    const float angle = angle_at(i);
    const UnitCirclePoint p = unit_circle_point(angle);
    worst =
        std::fmax(worst, std::fmax(std::fabs(p.c - std::cos(double(angle))), std::fabs(p.s - std::sin(double(angle)))));
  }
  EXPECT_LE(worst, kBound);
  EXPECT_GT(worst, 0.0);  // a polynomial, not the library's functions
}

// The device may contract the polynomials into fused multiply-adds: its points
// are held to the same bound, not to the host's bits.
TEST(UnitCircle, IsWithinItsBoundOnTheDevice) {
  const std::string source = kernel_program_source("mbao/unit_circle.h") + R"(
    __kernel void points(float angle_step, __global float2* out) {
      const UnitCirclePoint p = unit_circle_point((float)get_global_id(0) * angle_step);
      out[get_global_id(0)] = (float2)(p.c, p.s);
    })";
  const std::size_t n = 65537;
  const float angle_step = float(2.0 * M_PI / 65536.0);
  const std::vector<cl_float2> points = device_outputs<cl_float2>(source, "points", n, angle_step);
  for (std::size_t i = 0; i < n; ++i) {
    const double angle = double(float(i) * angle_step);
    ASSERT_NEAR(points[i].s[0], std::cos(angle), kBound) << "angle " << angle;
    ASSERT_NEAR(points[i].s[1], std::sin(angle), kBound) << "angle " << angle;
  }
}

}  // namespace
}  // namespace mbao
