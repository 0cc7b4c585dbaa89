#include "bake/bake_estimates.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "mbao/pixel_order.h"
#include "render/setting_specs.h"

namespace mbao {
namespace {

// One path per estimate (SPEC 6): the branching estimator with r = 1 is that
// path, with the path estimator's random numbers, and runs in every
// organisation the plan may pick; past its bounce limit the path estimator
// computes the same.
void set_one_path(RenderSettings& s) {
  s.samples = 1;
  s.estimator = s.bounces <= kMaxBranchingBounces ? Estimator::Branching : Estimator::Path;
}

}  // namespace

BakeEstimates bake_estimates(Renderer& renderer, const std::shared_ptr<const Scene>& scene, RenderSettings settings,
                             std::int64_t samples, const EstimatePoints& points, std::size_t layout_width,
                             const Renderer::TileCallback& between_tiles) {
  if (samples < kMinBakeSamples || samples > kMaxBakeSamples)
    throw std::invalid_argument("samples must be in [" + std::to_string(kMinBakeSamples) + ", " +
                                std::to_string(kMaxBakeSamples) + "] (estimates per vertex or texel; a standard "
                                "error needs two), got " + std::to_string(samples));
  BakeEstimates bake;
  bake.values.assign(points.targets(), 1.0f);
  bake.standard_error.assign(points.targets(), 0.0f);
  // Only the targets that hold surface are traced, in their order: no work item
  // is spent on a texel no UV reaches, and neighbours stay neighbours.
  std::vector<std::uint32_t> traced;
  for (std::size_t t = 0; t < points.targets(); ++t)
    if (points.has_surface(t)) traced.push_back(std::uint32_t(t));
  const std::size_t targets = traced.size();
  if (targets == 0) return bake;
  // Wider than asked where the image would be taller than a render's may be.
  const auto side = std::size_t(std::get<std::int64_t>(setting_spec("height").hi));
  const std::size_t width = std::min(targets, std::max({layout_width, (targets + side - 1) / side, std::size_t(1)}));
  const std::size_t height = (targets + width - 1) / width;
  if (width > side)
    throw std::invalid_argument("a bake of " + std::to_string(targets) + " vertices or texels is more than the " +
                                std::to_string(side * side) + " that one bake can hold; bake the scene in parts");
  settings.width = std::int64_t(width);
  settings.height = std::int64_t(height);
  settings.spp = samples;
  set_one_path(settings);
  const std::uint64_t seed = settings.seed;

  const auto points_of_tile = [&](std::size_t first, std::size_t count, std::vector<cl_uint4>& tile) {
    constexpr cl_uint4 kNoSurface{{0u, 0xFFFFFFFFu, 0u, 0u}};
    const auto n = std::size_t(samples);
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t pixel = pixel_at_position(std::uint32_t(first + i), std::uint32_t(width),
                                                    std::uint32_t(height));
      for (std::size_t k = 0; k < n; ++k) {
        const std::optional<SurfacePoint> p =
            pixel < targets ? points.point(traced[pixel], estimate_random(traced[pixel], std::uint32_t(k), seed))
                            : std::nullopt;
        tile[i * n + k] = p ? cl_uint4{{0u, p->triangle, mbao_float_as_u32(p->b1), mbao_float_as_u32(p->b2)}}
                            : kNoSurface;
      }
    }
  };
  RenderResult result = renderer.bake(scene, settings, points_of_tile, between_tiles);
  const double n = double(samples);
  for (std::size_t pixel = 0; pixel < targets; ++pixel) {
    const double mean = result.ao[pixel];
    const double variance = std::max(0.0, double(result.ao_second_moment[pixel]) - mean * mean) * n / (n - 1.0);
    bake.values[traced[pixel]] = result.ao[pixel];
    bake.standard_error[traced[pixel]] = float(std::sqrt(variance / n));
  }
  bake.stats = std::move(result.stats);
  return bake;
}

}  // namespace mbao
