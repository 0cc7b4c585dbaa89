#pragma once

// The settings of a bake that a render has not (SPEC 6), as mbao.bake and
// `python -m mbao bake` take them; render/setting_specs.h holds their table.
// A bake also takes the render's bounces, rho, normals, seed, max_rays and
// radius, and the texture's size, UV set and wrap modes, which are no scalars.

#include <cstdint>
#include <string>

#include "bake/bake_estimates.h"
#include "bake/dilation.h"
#include "render/render_settings.h"

namespace mbao {

struct BakeSettings {
  std::string target = "vertices";        // "vertices" (SPEC 6.2) or "texture" (SPEC 6.3)
  std::int64_t samples = 256;             // estimates per vertex or texel
  Estimator estimator = Estimator::Path;  // how each estimate traces from its point
  std::int64_t directions = 4;            // r
  std::int64_t padding = 4;               // texels dilated around the covered ones

  // Throws std::invalid_argument naming the first setting outside its range.
  void validate() const;
};

}  // namespace mbao
