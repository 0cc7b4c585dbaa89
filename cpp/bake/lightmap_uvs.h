// A new UV set for a bake (texcoord="generate", SPEC 6.3): charts laid flat
// (bake/uv_charts.h), projected or by conformal maps, whichever pack better,
// long strips cut across, packed into the texture by their outlines
// (bake/chart_packing.h) at one texel density.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include <optional>

#include "bake/texel_layout.h"
#include "bake/uv_charts.h"
#include "scene/triangle_mesh.h"

namespace mbao {

struct LightmapUvs {
  std::vector<glm::vec2> corner_uvs;  // three per triangle asked for, in its corners' order
  std::size_t charts = 0;
  // The largest factor by which a chart lengthens or shortens a direction in
  // one of its triangles (LaidCharts::worst_stretch of the charts kept): at
  // most 1 / kChartCosine.
  double worst_stretch = 1.0;
  double texels_per_unit = 0.0;  // the density: texels along a world unit of a chart's plane
  // Texels between charts: the padding asked for, or the largest smaller one
  // at which the charts fit; then size_keeping_padding is the texture size
  // (the one asked for times a power of two, at most kMaxTextureSide) at which
  // they would fit the padding asked for, if any.
  int padding = 0;
  std::optional<glm::ivec2> size_keeping_padding;
  std::optional<TexelLayout> layout;  // of corner_uvs in the texture (REPEAT), which nothing claims twice
};

// Charts for `triangles` of `mesh` (neighbours: triangles sharing an edge
// between equal positions), packed into width x height texels with `padding`
// texels between the texels they touch and half that around the border
// (fewer where they fit only so), at the largest density that fits.
// Triangles of zero area get UVs of zero area. Throws std::invalid_argument
// where the charts cannot fit even a texel each and touching.
LightmapUvs generate_lightmap_uvs(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles, int width,
                                  int height, int padding);

}  // namespace mbao
