// A bake's estimates traced by the renderer: the mean of L_b and its standard
// error per target (SPEC 6.4).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "bake/estimate_points.h"
#include "render/renderer.h"

namespace mbao {

struct BakeEstimates {
  std::vector<float> values, standard_error;  // per target; 1 and 0 where it holds no surface
  RenderStats stats;
};

// The estimates per target that a bake may ask for: the standard error needs two.
constexpr std::int64_t kMinBakeSamples = 2;
constexpr std::int64_t kMaxBakeSamples = std::int64_t(1) << 16;

// Where a bake's estimates go: the targets that hold surface, in their order,
// each one's estimates over `chunks` pixels of `per_pixel`, laid out as an
// image of width x height. One layout for the whole bake, so that any split of
// its positions traces the same rays (Renderer::bake).
struct BakeLayout {
  std::vector<std::uint32_t> traced;
  std::size_t chunks = 0, per_pixel = 0, pixels = 0, width = 0, height = 0;
  std::size_t positions() const { return width * height; }
};

// The layout of `samples` estimates of each target of `points` in an image
// `layout_width` wide where that fits (a texture's own width: neighbouring
// texels then trace neighbouring rays). Throws std::invalid_argument for
// samples out of range and a bake too large for one image.
BakeLayout bake_layout(const EstimatePoints& points, std::int64_t samples, std::size_t layout_width);

// The positions [first_position, end_position) of a layout's image, traced:
// each one's mean and mean square.
struct TracedPositions {
  std::vector<float> mean, second_moment;  // by position, from first_position
  RenderStats stats;
};
TracedPositions trace_bake(Renderer& renderer, const std::shared_ptr<const Scene>& scene, RenderSettings settings,
                           const EstimatePoints& points, const BakeLayout& layout, std::size_t first_position,
                           std::size_t end_position, const Renderer::TileCallback& between_tiles = {});

// Each target's value and standard error from all positions of the layout's image.
BakeEstimates finish_bake(const EstimatePoints& points, const BakeLayout& layout, std::int64_t samples,
                          const std::vector<float>& mean, const std::vector<float>& second_moment);

// Bakes settings.bounces, samples (r), estimator, rho, max_distance (unset:
// inf), normals and seed, with the engine settings as given, taking `samples`
// estimates of each target of `points`, each at a point of its own with r
// directions there (SPEC 2, 6). The targets that hold surface are laid out, in
// their order, as an image `layout_width` wide (a texture's own width:
// neighbouring texels then trace neighbouring rays), whose other settings this
// sets. Throws std::invalid_argument for bad settings and refuses, as a render
// does, work beyond settings.max_rays.
BakeEstimates bake_estimates(Renderer& renderer, const std::shared_ptr<const Scene>& scene, RenderSettings settings,
                             std::int64_t samples, const EstimatePoints& points, std::size_t layout_width,
                             const Renderer::TileCallback& between_tiles = {});

}  // namespace mbao
