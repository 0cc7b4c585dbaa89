#pragma once

#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "scene/alpha_mask_builder.h"
#include "scene/alpha_masks.h"
#include "scene/gltf_accessor_reader.h"
#include "scene/image_alpha.h"

namespace mbao {

// Turns a glTF file's MASK materials into AlphaMasks (SPEC 3.2), decoding
// only the images those materials use, and only their alpha.
class GltfAlphaMasks {
 public:
  enum class Coverage { Opaque, Transparent, Masked };
  struct Material {
    Coverage coverage = Coverage::Opaque;
    std::uint32_t texture = 0;  // with Masked: the MaskTexture
    int texcoord_set = 0;       // with Masked: n of the TEXCOORD_n attribute
    // With Masked: KHR_texture_transform's affine map of the UVs, rows (a, b, c) and (d, e, f):
    // (u, v) -> (a u + b v + c, d u + e v + f); the identity without the extension.
    std::array<float, 6> uv_transform = {1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};

    // `uv` (2 floats per vertex) through uv_transform.
    std::vector<float> transformed(std::vector<float> uv) const;
  };

  // `path` names the file in messages; relative image URIs are found in
  // `base_dir`; an image that cannot be read or decoded adds to `warnings`.
  GltfAlphaMasks(const tinygltf::Model& model, const AccessorReader& accessors, std::string path,
                 std::filesystem::path base_dir, std::vector<std::string>& warnings);

  // What material `index` (-1: none) means for AO: everything but a MASK
  // material with an alpha texture, or with a constant alpha below the cutoff, is opaque.
  Material material(int index);

  // The triangles' masks, added in the scene's order.
  AlphaMaskBuilder& triangles() { return builder_; }

  AlphaMasks take() { return builder_.take(); }

 private:
  Material resolve(int index);
  void read_texture_transform(const tinygltf::TextureInfo& info, const std::string& what, Material& material) const;
  std::optional<std::uint32_t> mask_texture(int texture_index, float alpha_factor, float cutoff,
                                            const std::string& what);
  std::optional<AlphaImage> alpha_image(int image_index, const std::string& what);
  std::vector<unsigned char> encoded_image(int image_index, const std::string& what) const;

  const tinygltf::Model& model_;
  const AccessorReader& accessors_;
  std::string path_;
  std::filesystem::path base_dir_;
  std::vector<std::string>& warnings_;
  AlphaMaskBuilder builder_;
  std::map<int, Material> materials_;
  // (image, wrap, alpha factor, cutoff) -> MaskTexture (none: the image is unreadable), so an image decodes
  // once per use.
  std::map<std::tuple<int, std::uint32_t, float, float>, std::optional<std::uint32_t>> textures_;
};

// Keeps the encoded bytes of images embedded as data URIs (tinygltf decodes
// the URI but keeps only what this returns); others are left unread or
// undecoded. Install with TinyGLTF::SetImageLoader.
bool keep_data_uri_images(tinygltf::Image* image, const int index, std::string* error, std::string* warning, int width,
                          int height, const unsigned char* bytes, int size, void* user_data);

}  // namespace mbao
