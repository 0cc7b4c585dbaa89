// The generator every random decision of the renderer comes from: Random123's
// known answers on the host, and the same numbers from the device.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "device_outputs.h"
#include "mbao/philox.h"
#include "opencl/kernel_sources.h"

namespace mbao {
namespace {

struct KnownAnswer {
  Philox4x32 counter;
  mbao_u32 key0, key1;
  Philox4x32 expected;
};

// Random123 v1.14.0, tests/kat_vectors, the three "philox4x32 10" lines.
const KnownAnswer kKnownAnswers[] = {
    {{{0, 0, 0, 0}}, 0, 0, {{0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8}}},
    {{{0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff}},
     0xffffffff,
     0xffffffff,
     {{0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd}}},
    {{{0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344}},
     0xa4093822,
     0x299f31d0,
     {{0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1}}},
};

TEST(Philox, MatchesRandom123KnownAnswersOnTheHost) {
  for (const KnownAnswer& k : kKnownAnswers) {
    const Philox4x32 out = philox4x32_10(k.counter, k.key0, k.key1);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(out.v[i], k.expected.v[i]) << "word " << i;
  }
}

TEST(Philox, UnitFloatsAreInTheHalfOpenUnitInterval) {
  EXPECT_EQ(philox_unit_float(0u), 0.0f);
  EXPECT_LT(philox_unit_float(0xFFFFFFFFu), 1.0f);
  EXPECT_EQ(philox_unit_float(0x80000000u), 0.5f);
}

TEST(Philox, DeviceProducesTheHostsNumbers) {
  const std::string source = kernel_program_source("mbao/philox.h") + R"(
    __kernel void draw(__global uint4* out) {
      const uint i = get_global_id(0);
      Philox4x32 c;
      c.v[0] = i; c.v[1] = 7u * i; c.v[2] = 0xdeadbeefu; c.v[3] = i ^ 0x12345678u;
      const Philox4x32 r = philox4x32_10(c, 0x9e3779b9u, i);
      out[i] = (uint4)(r.v[0], r.v[1], r.v[2], r.v[3]);
    })";
  const std::size_t n = 1000;
  const std::vector<cl_uint4> device_words = device_outputs<cl_uint4>(source, "draw", n);
  for (mbao_u32 i = 0; i < n; ++i) {
    const Philox4x32 host = philox4x32_10({{i, 7u * i, 0xdeadbeefu, i ^ 0x12345678u}}, 0x9e3779b9u, i);
    for (int w = 0; w < 4; ++w) ASSERT_EQ(device_words[i].s[w], host.v[w]) << "counter " << i << " word " << w;
  }
}

}  // namespace
}  // namespace mbao
