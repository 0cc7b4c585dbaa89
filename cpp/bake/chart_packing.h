// Packing generated charts into a texture by their outlines (SPEC 6.3): each
// chart's texels, not its box, keep `padding` texels from every other's.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>

namespace mbao {

// A chart laid flat: its triangles' corners in its plane, measured from its
// box's low corner, in world units.
struct FlatChart {
  std::vector<glm::dvec2> corners;  // three per triangle
  glm::dvec2 size{0.0};             // its box's
};

// Where each chart goes at `density` texels per world unit: the texel of its
// box's low corner, where its corner (0, 0) lies half a texel in from that
// texel's low corner. Each box (ceil(size * density) + 1 texels each way) lies
// `padding` texels from the border, and the texels each chart's triangles
// touch lie more than `padding` texels (in x or y) from those of every other.
// Charts go in `order`, each as high up and then as far left as it fits (first
// fit, into any gap the charts before it left). None where they do not fit.
std::optional<std::vector<glm::ivec2>> packed_charts(const std::vector<FlatChart>& charts,
                                                     const std::vector<std::size_t>& order, double density,
                                                     int width, int height, int padding);

}  // namespace mbao
