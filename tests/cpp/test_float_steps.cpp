// kernels/mbao/float_steps.h: the library's nextafter, ilogb and ldexp, bit for
// bit, from the floats' bits, on the host and on the device.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "device_outputs.h"
#include "mbao/float_steps.h"
#include "opencl/kernel_sources.h"

namespace mbao {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

std::uint32_t bits_of(float f) { return mbao_float_as_u32(f); }

// Every finite float's class: zeros, denormals, normals of every exponent, the
// largest, both signs, then random bit patterns.
std::vector<float> finite_floats() {
  std::vector<float> values = {0.0f, -0.0f, std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()};
  for (const std::uint32_t bits : {0x00000001u, 0x00000002u, 0x007fffffu, 0x00400000u, 0x00800000u, 0x3f800000u})
    for (const std::uint32_t sign : {0u, 0x80000000u}) values.push_back(mbao_u32_as_float(bits | sign));
  for (int exponent = -149; exponent <= 127; ++exponent) values.push_back(std::ldexp(1.0f, exponent));
  std::mt19937 random(7);
  while (values.size() < 200000) {
    const float x = mbao_u32_as_float(std::uint32_t(random()));
    if (std::isfinite(x)) values.push_back(x);
  }
  return values;
}

TEST(FloatSteps, AStepTowardASignIsNextafterTowardThatInfinity) {
  for (const float x : finite_floats()) {
    ASSERT_EQ(bits_of(float_step_toward(x, 1e-30f)), bits_of(std::nextafter(x, kInfinity))) << x;
    ASSERT_EQ(bits_of(float_step_toward(x, -3.0f)), bits_of(std::nextafter(x, -kInfinity))) << x;
    ASSERT_EQ(bits_of(float_step_toward(x, 0.0f)), bits_of(x)) << x;
    ASSERT_EQ(bits_of(float_step_toward(x, -0.0f)), bits_of(x)) << x;
  }
}

TEST(FloatSteps, TheInversePowerOfTwoIsTwoToMinusIlogb) {
  for (const float v : finite_floats()) {
    const float x = std::fabs(v);
    if (x == 0.0f) continue;
    const PowerOfTwo p = inverse_power_of_two(x);
    ASSERT_TRUE(std::isnormal(p.high) && std::isnormal(p.low)) << x;
    ASSERT_EQ(double(p.high) * double(p.low), std::ldexp(1.0, -std::ilogb(x))) << x;
  }
}

// What unit_scale and interpolated_normal rely on: scaling by the two factors
// in turn is ldexp for every value from x 2^-62 to x, of either sign.
TEST(FloatSteps, ScalingByBothFactorsIsLdexpFromXTimesTwoToMinus62ToX) {
  std::mt19937 random(11);
  std::uniform_real_distribution<float> fraction(0.0f, 1.0f);
  for (const float v : finite_floats()) {
    const float x = std::fabs(v);
    if (x == 0.0f) continue;
    const PowerOfTwo p = inverse_power_of_two(x);
    const int scale = -std::ilogb(x);
    for (int k = 0; k < 4; ++k) {
      const float below = std::ldexp(x, -int(62.0f * fraction(random))) * (k % 2 ? -1.0f : 1.0f);
      ASSERT_EQ(bits_of(below * p.high * p.low), bits_of(std::ldexp(below, scale))) << below << " under " << x;
    }
    ASSERT_EQ(bits_of(x * p.high * p.low), bits_of(std::ldexp(x, scale))) << x;
  }
}

// The kernels' copies: the same bits as the host's for inputs made from the
// work item's index (a hash of it, as a float, NaNs and infinities left out).
// Zeros are told by their bits, as a device may flush denormals in comparisons.
TEST(FloatSteps, TheDeviceStepsAsTheHost) {
  const std::string source = kernel_program_source("mbao/float_steps.h") + R"(
    static float input(uint i) {
      const float x = as_float(i * 2654435761u);
      return isfinite(x) ? x : (float)i;
    }
    __kernel void steps(__global uint4* out) {
      const float x = input(get_global_id(0));
      const PowerOfTwo p = inverse_power_of_two((as_uint(x) & 0x7fffffffu) ? fabs(x) : 1.0f);
      out[get_global_id(0)] = (uint4)(as_uint(float_step_toward(x, 1.0f)), as_uint(float_step_toward(x, -1.0f)),
                                      as_uint(p.high), as_uint(p.low));
    })";
  const std::size_t n = 1 << 18;
  const std::vector<cl_uint4> device = device_outputs<cl_uint4>(source, "steps", n);
  for (std::size_t i = 0; i < n; ++i) {
    float x = mbao_u32_as_float(std::uint32_t(i) * 2654435761u);
    if (!std::isfinite(x)) x = float(i);
    const PowerOfTwo p = inverse_power_of_two((bits_of(x) & 0x7fffffffu) ? std::fabs(x) : 1.0f);
    ASSERT_EQ(device[i].s[0], bits_of(float_step_toward(x, 1.0f))) << x;
    ASSERT_EQ(device[i].s[1], bits_of(float_step_toward(x, -1.0f))) << x;
    ASSERT_EQ(device[i].s[2], bits_of(p.high)) << x;
    ASSERT_EQ(device[i].s[3], bits_of(p.low)) << x;
  }
}

}  // namespace
}  // namespace mbao
