#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "mbao/alpha_mask.h"

namespace mbao {

// The alpha masks of a scene, in the layout the kernels read. Empty for a
// scene without MASK materials: then no mask data exists anywhere.
struct AlphaMasks {
  std::vector<MaskTexture> textures;
  std::vector<std::uint8_t> texels;  // every texture's alpha, 8 bits per texel
  std::vector<MaskedTriangle> triangles;
  // One per scene triangle: index into `triangles`, or MBAO_NOT_MASKED. Empty
  // when no triangle is masked.
  std::vector<std::uint32_t> triangle_mask;

  bool empty() const { return triangles.empty(); }
  std::size_t bytes() const {
    return textures.size() * sizeof(MaskTexture) + texels.size() + triangles.size() * sizeof(MaskedTriangle) +
           triangle_mask.size() * sizeof(std::uint32_t);
  }
};

}  // namespace mbao
