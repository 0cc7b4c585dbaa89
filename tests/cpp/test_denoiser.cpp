// The spatial filter of SPEC 7.3 on made-up images and G-buffers: it computes
// what the spec says, and so keeps a constant image, stays within its inputs,
// never mixes two surfaces that meet at an angle or a miss with a hit, and
// removes noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "mbao/gbuffer.h"
#include "opencl/compute_context.h"
#include "opencl/devices.h"
#include "render/denoiser.h"

namespace mbao {
namespace {

constexpr int kSide = 48;
constexpr float kFootprint = 0.01f;

struct Images {
  std::vector<GBufferTexel> gbuffer;
  std::vector<float> ao, variance;
  int width = kSide, height = kSide;
};

// A texel a camera ray hit at t = 1, a footprint wide, its shading normal the
// geometric one (the filter reads only the point, t, the normal and the footprint).
GBufferTexel hit_texel(float x, float y, float z, float nx, float ny, float nz) {
  return {x, y, z, 1.0f, nx, ny, nz, kFootprint, 1.0f, nx, ny, nz, 0};
}

// Every pixel on the plane z = 0, facing the eye, a footprint apart.
std::vector<GBufferTexel> facing_plane() {
  std::vector<GBufferTexel> g(kSide * kSide);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x)
      g[y * kSide + x] = hit_texel(x * kFootprint, -y * kFootprint, 0.0f, 0.0f, 0.0f, 1.0f);
  return g;
}

// The top half a wall (z = 0), the bottom half the floor it stands on (y = 0).
bool on_wall(int y) { return y < kSide / 2; }
std::vector<GBufferTexel> wall_on_floor() {
  std::vector<GBufferTexel> g(kSide * kSide);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const float along = x * kFootprint, from_edge = std::abs(y - kSide / 2 + 0.5f) * kFootprint;
      g[y * kSide + x] = on_wall(y) ? hit_texel(along, from_edge, 0.0f, 0.0f, 0.0f, 1.0f)
                                    : hit_texel(along, 0.0f, from_edge, 0.0f, 1.0f, 0.0f);
    }
  return g;
}

// `ao` and `variance` filtered by the device's Denoiser.
Images denoise(Images images, const DenoiseSettings& settings = {}) {
  ComputeContext compute(default_device());
  const cl::Program& program = compute.programs().get("denoise.cl", "").program;
  const auto buffer = [&](auto& host) {
    return cl::Buffer(compute.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, host.size() * sizeof(host[0]),
                      host.data());
  };
  std::vector<float> planes(GBUFFER_PLANES * images.gbuffer.size());
  for (std::size_t i = 0; i < images.gbuffer.size(); ++i)
    gbuffer_store(planes.data(), mbao_u32(images.gbuffer.size()), mbao_u32(i), images.gbuffer[i],
                  MBAO_GBUFFER_ALL_PLANES);
  const cl::Buffer gbuffer = buffer(planes), ao = buffer(images.ao), variance = buffer(images.variance);
  Denoiser denoiser(compute.context(), compute.device().device, program, images.width, images.height, settings);
  cl::CommandQueue& queue = compute.queue();
  denoiser.enqueue(queue, gbuffer, ao, variance);
  queue.enqueueReadBuffer(ao, CL_TRUE, 0, images.ao.size() * sizeof(float), images.ao.data());
  queue.enqueueReadBuffer(variance, CL_TRUE, 0, images.variance.size() * sizeof(float), images.variance.data());
  return images;
}

// Values uniform in [mean - half_width, mean + half_width], each with that distribution's variance.
void fill_noisy(Images& images, std::size_t first, std::size_t last, float mean, float half_width,
                std::mt19937& random) {
  std::uniform_real_distribution<float> noise(-half_width, half_width);
  for (std::size_t i = first; i < last; ++i) {
    images.ao[i] = mean + noise(random);
    images.variance[i] = half_width * half_width / 3.0f;
  }
}

Images sized(std::vector<GBufferTexel> gbuffer) {
  Images images;
  images.ao.resize(gbuffer.size());
  images.variance.resize(gbuffer.size());
  images.gbuffer = std::move(gbuffer);
  return images;
}

// SPEC 7.3 computed as it reads, in double.
Images filtered_as_specified(Images images, const DenoiseSettings& s) {
  const int width = images.width, height = images.height;
  const auto hit = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < width && y < height && images.gbuffer[y * width + x].t > 0.0f;
  };
  const double h1[3] = {6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0};
  for (int i = 0; i < s.iterations; ++i) {
    const int step = 1 << i;
    std::vector<float> ao = images.ao, variance = images.variance;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        if (!hit(x, y)) continue;
        double blurred = 0.0, blur_weights = 0.0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (hit(x + dx, y + dy)) {
              const double w = (2 - std::abs(dx)) * (2 - std::abs(dy));
              blurred += w * images.variance[(y + dy) * width + x + dx];
              blur_weights += w;
            }
        const int p = y * width + x;
        const GBufferTexel& gp = images.gbuffer[p];
        const double value_scale = s.sigma_value * std::sqrt(blurred / blur_weights) + 1e-6;
        double sum = 0.0, weights = 0.0, variance_sum = 0.0;
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const int qx = x + step * dx, qy = y + step * dy, q = qy * width + qx;
            if (!hit(qx, qy)) continue;
            const GBufferTexel& gq = images.gbuffer[q];
            const double plane = std::abs(double(gp.nx) * (gq.x - gp.x) + double(gp.ny) * (gq.y - gp.y) +
                                          double(gp.nz) * (gq.z - gp.z)) /
                                 (s.sigma_plane * gp.footprint);
            const double facing = std::max(0.0, double(gp.nx) * gq.nx + double(gp.ny) * gq.ny + double(gp.nz) * gq.nz);
            const double value = std::abs(double(images.ao[p]) - images.ao[q]) / value_scale;
            const double w = dx == 0 && dy == 0 ? 1.0 : std::exp(-plane - value) * std::pow(facing, s.sigma_normal);
            const double hw = h1[std::abs(dx)] * h1[std::abs(dy)] * w;
            sum += hw * images.ao[q];
            weights += hw;
            variance_sum += hw * hw * images.variance[q];
          }
        ao[p] = float(sum / weights);
        variance[p] = float(variance_sum / (weights * weights));
      }
    images.ao = std::move(ao);
    images.variance = std::move(variance);
  }
  return images;
}

// A width x height G-buffer of two planes at right angles (a floor and a wall
// with a step in depth) with bumps of up to a footprint off them, normals up
// to 0.1 rad off theirs and a tenth of the pixels missed, so that every weight
// takes values across (0, 1]; values and variances uniform.
Images rough_scene(int width, int height, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), signed_unit(-1.0f, 1.0f);
  Images images;
  images.width = width;
  images.height = height;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const bool wall = y < height / 2;
      const float along = x * kFootprint, across = y * kFootprint, bump = signed_unit(random) * kFootprint;
      const float tilt_a = 0.1f * signed_unit(random), tilt_b = 0.1f * signed_unit(random);
      const float depth = x < width / 3 ? 0.0f : 0.5f;
      GBufferTexel g = wall ? hit_texel(along, across, depth + bump, tilt_a, tilt_b, 1.0f)
                            : hit_texel(along, bump, across, tilt_a, 1.0f, tilt_b);
      const float length = std::sqrt(g.nx * g.nx + g.ny * g.ny + g.nz * g.nz);
      g.nx /= length, g.ny /= length, g.nz /= length;
      if (unit(random) < 0.1f) g.t = 0.0f;
      images.gbuffer.push_back(g);
      images.ao.push_back(unit(random));
      images.variance.push_back(0.05f * unit(random));
    }
  return images;
}

// Single precision against double: each weight is good to a few parts in 10^6,
// so each iteration's weighted means, of values in [0, 1] and of variances, to
// about 10^-5 (relative for the variances), and five iterations to 10^-4.
TEST(Denoiser, ComputesSpec73) {
  // 150 columns: an interior at every step, in groups that do not fill the
  // last; 20: none from step 4 on, the strips overlapping.
  for (const auto& [width, height, iterations] : {std::tuple{150, 37, 5}, std::tuple{20, 23, 4}}) {
    const Images images = rough_scene(width, height, 11);
    DenoiseSettings settings;
    settings.iterations = iterations;
    const Images device = denoise(images, settings), reference = filtered_as_specified(images, settings);
    for (std::size_t p = 0; p < images.ao.size(); ++p) {
      ASSERT_NEAR(device.ao[p], reference.ao[p], 1e-4) << width << " x " << height << ", pixel " << p;
      ASSERT_NEAR(device.variance[p], reference.variance[p], 1e-4 * reference.variance[p])
          << width << " x " << height << ", pixel " << p;
    }
  }
}

TEST(Denoiser, KeepsAConstantImage) {
  Images images = sized(facing_plane());
  std::mt19937 random(1);
  std::uniform_real_distribution<float> variance(0.0f, 0.05f);
  for (std::size_t i = 0; i < images.ao.size(); ++i) {
    images.ao[i] = 0.37f;
    images.variance[i] = variance(random);
  }
  const Images out = denoise(images);
  for (std::size_t i = 0; i < out.ao.size(); ++i) {
    ASSERT_NEAR(out.ao[i], 0.37f, 1e-6f) << "pixel " << i;
    ASSERT_GE(out.variance[i], 0.0f);
    ASSERT_LE(out.variance[i], images.variance[i] + 0.05f);
  }
}

TEST(Denoiser, StaysWithinItsInputs) {
  Images images = sized(facing_plane());
  std::mt19937 random(2);
  fill_noisy(images, 0, images.ao.size(), 0.5f, 0.5f, random);
  const auto [lo, hi] = std::minmax_element(images.ao.begin(), images.ao.end());
  const Images out = denoise(images);
  for (float v : out.ao) {
    ASSERT_GE(v, *lo);
    ASSERT_LE(v, *hi);
  }
}

// A variance so large that the values' weights let everything through: only
// the G-buffer's weights and the misses' exclusion keep the sides apart.
constexpr float kLargeVariance = 100.0f;

TEST(Denoiser, NeverMixesAWallWithTheFloorItStandsOn) {
  Images images = sized(wall_on_floor());
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      images.ao[y * kSide + x] = on_wall(y) ? 0.3f : 0.8f;
      images.variance[y * kSide + x] = kLargeVariance;
    }
  const Images out = denoise(images);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x)
      ASSERT_NEAR(out.ao[y * kSide + x], on_wall(y) ? 0.3f : 0.8f, 1e-6f) << "pixel (" << x << ", " << y << ")";
}

TEST(Denoiser, NeverMixesAcrossAStepInDepth) {
  Images images = sized(facing_plane());
  for (int y = 0; y < kSide; ++y)
    for (int x = kSide / 2; x < kSide; ++x) {  // the right half one unit farther back, its pixels twice as large
      GBufferTexel& g = images.gbuffer[y * kSide + x];
      g = hit_texel(2.0f * g.x, 2.0f * g.y, -1.0f, 0.0f, 0.0f, 1.0f);
      g.t = 2.0f;
      g.footprint = 2.0f * kFootprint;
    }
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      images.ao[y * kSide + x] = x < kSide / 2 ? 0.3f : 0.8f;
      images.variance[y * kSide + x] = kLargeVariance;
    }
  const Images out = denoise(images);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x)
      ASSERT_NEAR(out.ao[y * kSide + x], x < kSide / 2 ? 0.3f : 0.8f, 1e-6f) << "pixel (" << x << ", " << y << ")";
}

TEST(Denoiser, LeavesMissesAloneAndNeverTakesThemIn) {
  Images images = sized(facing_plane());
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const bool miss = x >= kSide / 2;  // the right half: 1, as a render stores it
      if (miss) images.gbuffer[y * kSide + x].t = 0.0f;
      images.ao[y * kSide + x] = miss ? 1.0f : 0.2f;
      images.variance[y * kSide + x] = kLargeVariance;
    }
  const Images out = denoise(images);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x)
      ASSERT_NEAR(out.ao[y * kSide + x], x >= kSide / 2 ? 1.0f : 0.2f, 1e-6f) << "pixel (" << x << ", " << y << ")";
}

TEST(Denoiser, RemovesMostOfTheNoiseOfAFlatSurface) {
  Images images = sized(facing_plane());
  std::mt19937 random(5);
  fill_noisy(images, 0, images.ao.size(), 0.5f, 0.2f, random);
  const auto rmse = [](const std::vector<float>& v) {
    double sum = 0.0;
    for (float x : v) sum += (x - 0.5) * (x - 0.5);
    return std::sqrt(sum / double(v.size()));
  };
  const Images out = denoise(images);
  EXPECT_LT(rmse(out.ao), rmse(images.ao) / 3.0);  // the target for the denoiser: a third
}

TEST(Denoiser, PropagatesTheVarianceWithTheSquaredWeights) {
  // A constant image on a flat surface: every weight is 1 but the spline's, so
  // an interior pixel's variance shrinks by (sum of h1^2)^2 = (70 / 256)^2 per iteration.
  Images images = sized(facing_plane());
  std::fill(images.ao.begin(), images.ao.end(), 0.5f);
  std::fill(images.variance.begin(), images.variance.end(), 0.01f);
  DenoiseSettings two;
  two.iterations = 2;
  const Images out = denoise(images, two);
  const double shrink = std::pow(70.0 / 256.0, 2);
  EXPECT_NEAR(out.variance[(kSide / 2) * kSide + kSide / 2], 0.01 * shrink * shrink, 1e-9);
}

TEST(Denoiser, RefusesSettingsOutOfRange) {
  DenoiseSettings s;
  s.iterations = 0;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s = DenoiseSettings{};
  s.sigma_value = 0.0f;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s = DenoiseSettings{};
  s.sigma_normal = -1;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  EXPECT_NO_THROW(DenoiseSettings{}.validate());
}

}  // namespace
}  // namespace mbao
