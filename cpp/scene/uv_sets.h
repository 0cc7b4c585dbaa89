// The texture coordinates and materials a texture bake reads (SPEC 6.3),
// loaded from a file only when asked for: renders never read them.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "scene/wrap_mode.h"

namespace mbao {

// A material's base colour as bake_file writes it for a file of another
// format (LoadOptions::base_colors; a glTF file keeps its own materials).
struct BaseColor {
  std::array<float, 4> factor{1.0f, 1.0f, 1.0f, 1.0f};  // glTF's baseColorFactor: colour, and opacity
  std::vector<unsigned char> image;  // PNG or JPEG bytes; empty where it has none or it could not be read
  int texcoord = 0;                  // the UV set the image is looked up in
  WrapMode wrap_s = WrapMode::Repeat, wrap_t = WrapMode::Repeat;
};

struct MaterialUvs {
  std::string name;
  int occlusion_texcoord = -1;  // its occlusionTexture's texCoord; -1 where it has none
  // Its occlusion texture's sampler; glTF's default where it has none.
  WrapMode wrap_s = WrapMode::Repeat, wrap_t = WrapMode::Repeat;
  std::optional<BaseColor> base_color;  // read only where asked for
};

// Where a primitive of the file went: which node placed which mesh's
// primitive, and its vertices and triangles in the scene (a mesh placed by two
// nodes is there twice).
struct LoadedPrimitive {
  int node, mesh, primitive;
  std::size_t first_vertex, vertex_count, first_triangle, triangle_count;
};

// The UV sets read: TEXCOORD_0 to TEXCOORD_7 (an Assimp format's channels 0 to 7).
constexpr int kMaxUvSets = 8;

struct UvSets {
  bool loaded = false;
  std::vector<std::vector<glm::vec2>> sets;      // sets[n][v]: vertex v's TEXCOORD_n; NaN where its primitive has none
  std::vector<std::int32_t> triangle_materials;  // per triangle: its material, -1 for none
  std::vector<MaterialUvs> materials;            // the file's materials, in its order
  std::vector<LoadedPrimitive> primitives;       // those that brought triangles, in the scene's order
};

}  // namespace mbao
