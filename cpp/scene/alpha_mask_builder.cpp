#include "scene/alpha_mask_builder.h"

#include <limits>

#include "core/error.h"

namespace mbao {

std::uint32_t AlphaMaskBuilder::add_texture(const AlphaImage& image, std::uint32_t wrap, float alpha_factor,
                                            float cutoff, const std::string& what) {
  if (!image.has_alpha) return MBAO_NOT_MASKED;
  if (image.alpha.size() > std::numeric_limits<std::uint32_t>::max() - masks_.texels.size())
    throw LoadError(path_ + ": " + what + " brings the alpha masks past 2^32 texels, more than 32-bit offsets reach");
  MaskTexture mask{};
  mask.first_texel = std::uint32_t(masks_.texels.size());
  mask.width = std::uint32_t(image.width);
  mask.height = std::uint32_t(image.height);
  mask.wrap = wrap;
  mask.alpha_factor = alpha_factor;
  mask.cutoff = cutoff;
  masks_.texels.insert(masks_.texels.end(), image.alpha.begin(), image.alpha.end());
  masks_.textures.push_back(mask);
  return std::uint32_t(masks_.textures.size() - 1);
}

void AlphaMaskBuilder::reserve(std::size_t masked, std::size_t triangles) {
  masks_.triangles.reserve(masked);
  expected_triangles_ = triangles;
}

void AlphaMaskBuilder::add_opaque(std::size_t count) {
  triangles_ += count;
  if (!masks_.triangle_mask.empty()) masks_.triangle_mask.resize(triangles_, MBAO_NOT_MASKED);
}

void AlphaMaskBuilder::add_masked(const std::vector<std::uint32_t>& indices, const std::vector<float>& uv,
                                  std::uint32_t texture) {
  if (masks_.triangle_mask.empty()) masks_.triangle_mask.reserve(expected_triangles_);
  masks_.triangle_mask.resize(triangles_, MBAO_NOT_MASKED);
  for (std::size_t t = 0; t < indices.size(); t += 3) {
    MaskedTriangle triangle{};
    for (int k = 0; k < 3; ++k) {
      triangle.uv[2 * k] = uv[2 * std::size_t(indices[t + std::size_t(k)])];
      triangle.uv[2 * k + 1] = uv[2 * std::size_t(indices[t + std::size_t(k)]) + 1];
    }
    triangle.texture = texture;
    masks_.triangle_mask.push_back(std::uint32_t(masks_.triangles.size()));
    masks_.triangles.push_back(triangle);
  }
  triangles_ += indices.size() / 3;
}

}  // namespace mbao
