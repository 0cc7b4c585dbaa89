// Filling a texture's empty texels from their covered neighbours (SPEC 6.3),
// so that bilinear and mipmapped lookups near a chart's border never reach one.
#pragma once

#include <cstdint>
#include <vector>

namespace mbao {

// The widest padding a bake takes, in texels.
constexpr int kMaxPadding = 64;

// Each texel of a width x height image (row by row) that is not covered takes
// the value of the nearest covered texel (by the distance between centres; the
// first in row order among equals) within `padding` texels along both axes, in
// every one of `channels`; the search does not wrap around the edges. Returns
// which texels were filled.
std::vector<std::uint8_t> dilate(const std::vector<std::uint8_t>& covered, int width, int height, int padding,
                                 const std::vector<std::vector<float>*>& channels);

}  // namespace mbao
