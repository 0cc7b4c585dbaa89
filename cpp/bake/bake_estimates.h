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
