#include "bake/bake_estimates.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>

#include "bake/bake_settings.h"
#include "mbao/pixel_order.h"
#include "render/setting_specs.h"

namespace mbao {
namespace {

// Fewer targets than this share their estimates out over several pixels, so
// that a bake of a small mesh still gives every core and compute unit work items.
constexpr std::size_t kMinBakePixels = std::size_t(1) << 16;

// The pixels each target's estimates are spread over: the least divisor of
// `samples` that makes kMinBakePixels in all, else one per estimate. A
// divisor, so that every pixel holds as many estimates and their means add up.
std::size_t pixels_per_target(std::size_t targets, std::size_t samples) {
  for (std::size_t d = 1; d < samples; ++d)
    if (samples % d == 0 && targets * d >= kMinBakePixels) return d;
  return samples;
}

}  // namespace

BakeLayout bake_layout(const EstimatePoints& points, std::int64_t samples, std::size_t layout_width) {
  BakeSettings asked;
  asked.samples = samples;
  asked.validate();
  BakeLayout layout;
  // Only the targets that hold surface are traced, in their order: no work item
  // is spent on a texel no UV reaches, and neighbours stay neighbours.
  for (std::size_t t = 0; t < points.targets(); ++t)
    if (points.has_surface(t)) layout.traced.push_back(std::uint32_t(t));
  const std::size_t targets = layout.traced.size();
  if (targets == 0) return layout;
  // Target i's estimates fill pixels i * chunks .. i * chunks + chunks - 1,
  // `per_pixel` each, in the order of their numbers.
  layout.chunks = pixels_per_target(targets, std::size_t(samples));
  layout.per_pixel = std::size_t(samples) / layout.chunks;
  layout.pixels = targets * layout.chunks;
  // Wider than asked where the image would be taller than a render's may be.
  const auto side = std::size_t(std::get<std::int64_t>(setting_spec("height").hi));
  layout.width =
      std::min({layout.pixels, side,
                std::max({layout_width * layout.chunks, (layout.pixels + side - 1) / side, std::size_t(1)})});
  layout.height = (layout.pixels + layout.width - 1) / layout.width;
  if (layout.height > side)
    throw std::invalid_argument("a bake of " + std::to_string(targets) + " vertices or texels is more than the " +
                                std::to_string(side * side) + " that one bake can hold; bake the scene in parts");
  return layout;
}

TracedPositions trace_bake(Renderer& renderer, const std::shared_ptr<const Scene>& scene, RenderSettings settings,
                           const EstimatePoints& points, const BakeLayout& layout, std::size_t first_position,
                           std::size_t end_position, const Renderer::TileCallback& between_tiles) {
  TracedPositions traced;
  end_position = std::min(end_position, layout.positions());
  if (first_position >= end_position) return traced;
  const std::size_t width = layout.width, height = layout.height, chunks = layout.chunks;
  const std::size_t per_pixel = layout.per_pixel, pixels = layout.pixels;
  settings.width = std::int64_t(width);
  settings.height = std::int64_t(height);
  settings.spp = std::int64_t(per_pixel);
  const std::uint64_t seed = settings.seed;

  // The points of the tile's pixels [begin, end).
  const auto draw = [&](std::size_t first, std::size_t begin, std::size_t end, std::vector<cl_uint4>& tile) {
    constexpr cl_uint4 kNoSurface{{0u, 0xFFFFFFFFu, 0u, 0u}};
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t pixel =
          pixel_at_position(std::uint32_t(first + i), std::uint32_t(width), std::uint32_t(height));
      const std::uint32_t target = pixel < pixels ? layout.traced[pixel / chunks] : 0u;
      const std::size_t first_estimate = (pixel % chunks) * per_pixel;
      for (std::size_t k = 0; k < per_pixel; ++k) {
        const std::optional<SurfacePoint> p =
            pixel < pixels ? points.point(target, estimate_random(target, std::uint32_t(first_estimate + k), seed))
                           : std::nullopt;
        tile[i * per_pixel + k] =
            p ? cl_uint4{{0u, p->triangle, mbao_float_as_u32(p->b1), mbao_float_as_u32(p->b2)}} : kNoSurface;
      }
    }
  };
  // On every core: a GPU traces the points faster than one thread draws them.
  const std::size_t threads = std::max(1u, std::thread::hardware_concurrency());
  const auto points_of_tile = [&](std::size_t first, std::size_t count, std::vector<cl_uint4>& tile) {
    const std::size_t slice = (count + threads - 1) / threads;
    std::vector<std::future<void>> slices;
    for (std::size_t begin = slice; begin < count; begin += slice)
      slices.push_back(
          std::async(std::launch::async, draw, first, begin, std::min(count, begin + slice), std::ref(tile)));
    draw(first, 0, std::min(count, slice), tile);
    for (std::future<void>& part : slices) part.get();
  };
  RenderResult result = renderer.bake(scene, settings, points_of_tile, between_tiles, first_position, end_position);
  traced.mean.resize(end_position - first_position);
  traced.second_moment.resize(end_position - first_position);
  for (std::size_t p = first_position; p < end_position; ++p) {
    const std::uint32_t pixel = pixel_at_position(std::uint32_t(p), std::uint32_t(width), std::uint32_t(height));
    traced.mean[p - first_position] = result.ao[pixel];
    traced.second_moment[p - first_position] = result.ao_second_moment[pixel];
  }
  traced.stats = std::move(result.stats);
  return traced;
}

BakeEstimates finish_bake(const EstimatePoints& points, const BakeLayout& layout, std::int64_t samples,
                          const std::vector<float>& mean, const std::vector<float>& second_moment) {
  if (mean.size() != layout.positions() || second_moment.size() != layout.positions())
    throw std::invalid_argument("a bake's traced positions: " + std::to_string(mean.size()) + " means and " +
                                std::to_string(second_moment.size()) + " second moments, for " +
                                std::to_string(layout.positions()) + " positions");
  BakeEstimates bake;
  bake.values.assign(points.targets(), 1.0f);
  bake.standard_error.assign(points.targets(), 0.0f);
  std::vector<float> pixel_mean(layout.pixels), pixel_second_moment(layout.pixels);
  for (std::size_t p = 0; p < layout.positions(); ++p) {
    const std::uint32_t pixel =
        pixel_at_position(std::uint32_t(p), std::uint32_t(layout.width), std::uint32_t(layout.height));
    if (pixel >= layout.pixels) continue;
    pixel_mean[pixel] = mean[p];
    pixel_second_moment[pixel] = second_moment[p];
  }
  const double n = double(samples);
  const std::size_t chunks = layout.chunks;
  for (std::size_t i = 0; i < layout.traced.size(); ++i) {
    double target_mean = 0.0, target_second_moment = 0.0;
    for (std::size_t pixel = i * chunks; pixel < (i + 1) * chunks; ++pixel) {
      target_mean += pixel_mean[pixel];
      target_second_moment += pixel_second_moment[pixel];
    }
    target_mean /= double(chunks);
    target_second_moment /= double(chunks);
    const double variance = std::max(0.0, target_second_moment - target_mean * target_mean) * n / (n - 1.0);
    bake.values[layout.traced[i]] = float(target_mean);
    bake.standard_error[layout.traced[i]] = float(std::sqrt(variance / n));
  }
  return bake;
}

BakeEstimates bake_estimates(Renderer& renderer, const std::shared_ptr<const Scene>& scene, RenderSettings settings,
                             std::int64_t samples, const EstimatePoints& points, std::size_t layout_width,
                             const Renderer::TileCallback& between_tiles) {
  const BakeLayout layout = bake_layout(points, samples, layout_width);
  TracedPositions traced = trace_bake(renderer, scene, settings, points, layout, 0, layout.positions(), between_tiles);
  BakeEstimates bake = finish_bake(points, layout, samples, traced.mean, traced.second_moment);
  bake.stats = std::move(traced.stats);
  return bake;
}

}  // namespace mbao
