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

// A chart turned in its plane by `quarter_turns` quarter turns (x towards y),
// its corners measured again from its box's low corner.
FlatChart turned(const FlatChart& chart, int quarter_turns);

// Where a chart goes: the texel of its box's low corner, and by how many quarter turns it is turned first.
struct Placement {
  glm::ivec2 corner{0};
  int quarter_turns = 0;
};

// Where each chart goes at `density` texels per world unit, turned or not:
// the texel of its box's low corner, where its corner (0, 0) lies half a
// texel in from that texel's low corner. The texels each chart's triangles
// touch lie more than `padding` texels (in x or y) from those of every other,
// and each box (ceil(size * density) + 1 texels each way) half `padding`
// (rounded up) from the border, so that under REPEAT charts at opposite edges
// lie `padding` apart across it. Charts go in `order`, each as high up and
// then as far left as it fits, as it is or half turned, as it is where both
// fit at one place (first fit, into any gap the charts before it left; a half
// turn lets two triangles, or two concave charts, nest). A chart that fits neither way
// is tried a quarter turn either way, the same way: its long side, which lies
// along x, then stands along y. None where they do not fit.
std::optional<std::vector<Placement>> packed_charts(const std::vector<FlatChart>& charts,
                                                    const std::vector<std::size_t>& order, double density, int width,
                                                    int height, int padding);

}  // namespace mbao
