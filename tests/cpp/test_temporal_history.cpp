// SPEC 7.4's validity rules on made-up G-buffers: a still camera over a wall
// facing it, whose second frame tilts some pixels' normals or moves their
// points along their camera rays. Each pixel reprojects onto itself, so its
// history is kept exactly where the rules accept that one tap.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "mbao/gbuffer.h"
#include "opencl/compute_context.h"
#include "opencl/devices.h"
#include "render/ao_kernel_args.h"
#include "render/temporal_history.h"

namespace mbao {
namespace {

constexpr int kWidth = 8, kHeight = 32;  // the tests change row 0
constexpr float kFirstValue = 0.2f, kSecondValue = 0.6f;

const Camera kCamera{glm::vec3(0.0f, 0.0f, 5.0f), glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f), 40.0f, {}};

RenderSettings sized() {
  RenderSettings s;
  s.width = kWidth;
  s.height = kHeight;
  return s;
}

// Each pixel centre's hit on the wall z = 0, facing the eye (SPEC 7.2).
std::vector<GBufferTexel> wall() {
  const CameraBasis basis(kCamera);
  std::vector<GBufferTexel> g;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const glm::vec3 d = basis.direction(x + 0.5f, y + 0.5f, kWidth, kHeight);
      const float t = -kCamera.eye.z / d.z;
      const glm::vec3 p = kCamera.eye + t * d;
      const float depth = glm::dot(p - kCamera.eye, basis.forward);
      g.push_back(
          {p.x, p.y, p.z, t, 0.0f, 0.0f, 1.0f, 2.0f * t * basis.tan_half_vfov / kHeight, depth, 0.0f, 0.0f, 1.0f, 0});
    }
  return g;
}

// Accumulates two frames with the given G-buffers and constant values; the second frame's lengths.
std::vector<cl_uint> second_frame_lengths(const std::vector<GBufferTexel>& first,
                                          const std::vector<GBufferTexel>& second, std::vector<float>& values) {
  ComputeContext compute(default_device());
  const cl::Program& program = compute.programs().get("temporal.cl", "").program;
  cl::CommandQueue& queue = compute.queue();
  TemporalHistory history(TemporalSettings{});
  const CameraArgs camera(kCamera, sized());
  const std::size_t pixels = first.size();
  for (const auto* g : {&first, &second}) {
    std::vector<float> planes(GBUFFER_PLANES * pixels);
    for (std::size_t i = 0; i < pixels; ++i)
      gbuffer_store(planes.data(), mbao_u32(pixels), mbao_u32(i), (*g)[i], MBAO_GBUFFER_ALL_PLANES);
    values.assign(pixels, g == &first ? kFirstValue : kSecondValue);
    std::vector<float> variance(pixels, 0.01f);
    FrameBuffers frame;
    const auto buffer = [&](std::vector<float>& host) {
      return cl::Buffer(compute.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, host.size() * sizeof(float),
                        host.data());
    };
    frame.gbuffer = buffer(planes);
    frame.ao = buffer(values);
    frame.ao_variance = buffer(variance);
    history.enqueue_accumulate(queue, compute.context(), program, frame, camera, 0);
    queue.enqueueReadBuffer(frame.ao, CL_TRUE, 0, pixels * sizeof(float), values.data());
  }
  std::vector<cl_uint> lengths(pixels);
  history.enqueue_read_lengths(queue, lengths);
  queue.finish();
  return lengths;
}

void expect_kept(const std::vector<cl_uint>& lengths, const std::vector<float>& values, int pixel, bool kept,
                 const char* what) {
  EXPECT_EQ(lengths[pixel], kept ? 2u : 1u) << what;
  EXPECT_FLOAT_EQ(values[pixel], kept ? (kFirstValue + kSecondValue) / 2 : kSecondValue) << what;
}

TEST(TemporalHistory, KeepsHistoryWhereTheNormalsAreWithinTheLimit) {
  const std::vector<GBufferTexel> first = wall();
  std::vector<GBufferTexel> second = first;
  const float degrees[kWidth] = {0.0f, 15.0f, 25.0f, 25.7f, 26.0f, 30.0f, 60.0f, 120.0f};  // cos 25.84 = 0.9
  for (int x = 0; x < kWidth; ++x) {
    const float a = degrees[x] * 3.14159265f / 180.0f;
    second[x].nx = std::sin(a);
    second[x].nz = std::cos(a);
  }
  std::vector<float> values;
  const std::vector<cl_uint> lengths = second_frame_lengths(first, second, values);
  for (int x = 0; x < kWidth; ++x)
    expect_kept(lengths, values, x, std::cos(degrees[x] * 3.14159265f / 180.0f) >= 0.9f,
                ("normals " + std::to_string(degrees[x]) + " degrees apart").c_str());
}

TEST(TemporalHistory, KeepsHistoryWithinTwoFootprintsOfTheTangentPlane) {
  const std::vector<GBufferTexel> first = wall();
  std::vector<GBufferTexel> second = first;
  const CameraBasis basis(kCamera);
  const float footprints[kWidth] = {0.0f, 0.5f, 1.5f, 1.9f, 2.1f, 3.0f, 10.0f, -2.5f};
  for (int x = 0; x < kWidth; ++x) {
    // Along the pixel's camera ray, so that it still reprojects onto its own centre.
    const glm::vec3 d = basis.direction(x + 0.5f, 0.5f, kWidth, kHeight);
    const float along = footprints[x] * first[x].footprint / std::abs(d.z);
    GBufferTexel& g = second[x];
    g.t -= along;
    g.x -= along * d.x, g.y -= along * d.y, g.z -= along * d.z;
  }
  std::vector<float> values;
  const std::vector<cl_uint> lengths = second_frame_lengths(first, second, values);
  for (int x = 0; x < kWidth; ++x)
    expect_kept(lengths, values, x, std::abs(footprints[x]) <= 2.0f,
                (std::to_string(footprints[x]) + " footprints off the plane").c_str());
}

TEST(TemporalHistory, AMissHasNoHistoryAndGivesNone) {
  std::vector<GBufferTexel> first = wall(), second = wall();
  first[3].t = 0.0f;   // missed in the first frame: no valid tap
  second[5].t = 0.0f;  // missed now: kept as rendered, length 0
  std::vector<float> values;
  const std::vector<cl_uint> lengths = second_frame_lengths(first, second, values);
  expect_kept(lengths, values, 3, false, "a pixel that missed before");
  EXPECT_EQ(lengths[5], 0u);
  EXPECT_FLOAT_EQ(values[5], kSecondValue);
  expect_kept(lengths, values, 4, true, "a neighbour of both");
}

}  // namespace
}  // namespace mbao
