#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "scene/alpha_masks.h"
#include "scene/image_alpha.h"

namespace mbao {

// Builds a scene's AlphaMasks (SPEC 3.2) triangle by triangle, as a loader
// adds its meshes in the scene's order: each triangle opaque or masked by a
// texture, with its corners' UVs.
class AlphaMaskBuilder {
 public:
  // `path` names the file in messages.
  explicit AlphaMaskBuilder(std::string path) : path_(std::move(path)) {}

  // A mask texture of `image`'s alpha (`what` names it in messages), sampled
  // with `wrap` (MBAO_WRAP_* for s | t << 2) and cut where alpha_factor *
  // alpha < cutoff; MBAO_NOT_MASKED for an image without alpha.
  std::uint32_t add_texture(const AlphaImage& image, std::uint32_t wrap, float alpha_factor, float cutoff,
                            const std::string& what);

  // Room for the masks of `masked` of the scene's `triangles` triangles.
  void reserve(std::size_t masked, std::size_t triangles);
  // The next `count` triangles of the scene are opaque.
  void add_opaque(std::size_t count);
  // The next triangles are masked: their corners are `indices` into `uv`
  // (2 floats per vertex, v down the image), sampled from `texture`.
  void add_masked(const std::vector<std::uint32_t>& indices, const std::vector<float>& uv, std::uint32_t texture);

  AlphaMasks take() { return std::move(masks_); }

 private:
  std::string path_;
  AlphaMasks masks_;
  std::size_t triangles_ = 0;
  std::size_t expected_triangles_ = 0;
};

}  // namespace mbao
