// The AO directions drawn four at a time on vectors (the lanes' stream) are
// the directions drawn one by one (the megakernel), bit for bit: the images
// hardly show a last-bit difference, so it is checked here, on the device.
#include <gtest/gtest.h>

#include <vector>

#include "device_outputs.h"
#include "opencl/kernel_sources.h"

namespace mbao {
namespace {

// Work item i draws nodes 4i .. 4i + 3 both ways around a normal of its own
// (the poles and the axes among them, where the basis changes sign) and counts
// the words and coordinates that differ.
const char* kCompare = R"(
  __kernel void compare(__global uint* mismatches) {
    const uint i = get_global_id(0);
    const uint2 seed = (uint2)(0x9e3779b9u, i);
    const float3 fixed_normals[6] = {(float3)(0.0f, 0.0f, 1.0f), (float3)(0.0f, 0.0f, -1.0f),
                                     (float3)(1.0f, 0.0f, 0.0f), (float3)(0.0f, -1.0f, 0.0f),
                                     (float3)(0.0f, -0.0f, 1.0f), (float3)(-0.0f, 0.0f, -1.0f)};
    const Philox4x32 g = random_block(i, 1u, 2u, 3u, (uint2)(7u, 8u));
    const float3 drawn = (float3)(philox_unit_float(g.v[0]), philox_unit_float(g.v[1]),
                                  philox_unit_float(g.v[2])) - 0.5f;
    const float3 n = i < 6 ? fixed_normals[i] : normalize(drawn);
    uint4 bits[4];
    random_blocks_x4(i, i % 3u, 1u + i % 2u, 4u * i, seed, bits);
    float4 x, y, z;
    cosine_directions_x4(n, philox_unit_floats(bits[0]), philox_unit_floats(bits[1]), &x, &y, &z);
    const float xs[4] = {x.s0, x.s1, x.s2, x.s3}, ys[4] = {y.s0, y.s1, y.s2, y.s3},
                zs[4] = {z.s0, z.s1, z.s2, z.s3};
    const uint words[4][4] = {{bits[0].s0, bits[1].s0, bits[2].s0, bits[3].s0},
                              {bits[0].s1, bits[1].s1, bits[2].s1, bits[3].s1},
                              {bits[0].s2, bits[1].s2, bits[2].s2, bits[3].s2},
                              {bits[0].s3, bits[1].s3, bits[2].s3, bits[3].s3}};
    uint differ = 0;
    for (uint j = 0; j < 4; ++j) {
      const Philox4x32 r = random_block(i, i % 3u, 1u + i % 2u, 4u * i + j, seed);
      for (uint k = 0; k < 4; ++k) differ += r.v[k] != words[j][k];
      const float3 d = cosine_direction(n, philox_unit_float(r.v[0]), philox_unit_float(r.v[1]));
      differ += (as_uint(d.x) != as_uint(xs[j])) + (as_uint(d.y) != as_uint(ys[j])) +
                (as_uint(d.z) != as_uint(zs[j]));
    }
    mismatches[i] = differ;
  })";

TEST(Sampling, DirectionsDrawnFourAtATimeAreTheDirectionsDrawnOneByOne) {
  const std::size_t n = 20000;
  const std::vector<cl_uint> mismatches =
      device_outputs<cl_uint>(kernel_program_source("sampling.h") + kCompare, "compare", n);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(mismatches[i], 0u) << "work item " << i;
}

}  // namespace
}  // namespace mbao
