#include "scene/assimp_scene.h"

#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "scene/alpha_mask_builder.h"
#include "scene/gltf_files.h"
#include "scene/gltf_image.h"
#include "scene/image_alpha.h"
#include "scene/texture_files.h"

namespace mbao {
namespace {

// The cutoff of a glTF MASK material by default, which masks from other formats take.
constexpr float kMaskCutoff = 0.5f;

std::uint32_t wrap_of(aiTextureMapMode mode) {
  switch (mode) {
    case aiTextureMapMode_Clamp:
    case aiTextureMapMode_Decal: return MBAO_WRAP_CLAMP_TO_EDGE;
    case aiTextureMapMode_Mirror: return MBAO_WRAP_MIRRORED_REPEAT;
    default: return MBAO_WRAP_REPEAT;
  }
}

// Image `file` of a material: one embedded in the scene ("*n", or named by
// its file name), or a file found beside the model, in `model_folder`. Given
// to `encoded(bytes, size)` where it is an encoded image (a file, or one
// embedded compressed), to `texels(texture)` where it is embedded as texels.
template <typename Encoded, typename Texels>
auto with_image(const aiScene& scene, const std::filesystem::path& model_folder, const aiString& file,
                const std::string& what, Encoded encoded, Texels texels) {
  if (const aiTexture* embedded = scene.GetEmbeddedTexture(file.C_Str()))
    return embedded->mHeight == 0  // compressed: mWidth bytes of an encoded image
               ? encoded(reinterpret_cast<const unsigned char*>(embedded->pcData), std::size_t(embedded->mWidth))
               : texels(*embedded);
  const std::vector<unsigned char> bytes = read_regular_file(find_texture_file(model_folder, file.C_Str()), what);
  return encoded(bytes.data(), bytes.size());
}

// The alpha masks of a file's materials (SPEC 3.2): a material's opacity map
// (OBJ map_d: its alpha, else its first channel), else the alpha of its
// diffuse map (map_Kd), times its opacity (OBJ d), cuts the surface where it
// is below 0.5, as a glTF MASK material with the default cutoff does.
class AssimpMasks {
 public:
  enum class Coverage { Opaque, Transparent, Masked };
  struct Material {
    Coverage coverage = Coverage::Opaque;
    std::uint32_t texture = MBAO_NOT_MASKED;
    unsigned uv_channel = 0;
  };

  // An image that cannot be read or decoded adds to `warnings`, and its material is opaque.
  // Without `honour_opacity`, every material's opacity is taken as 1.
  AssimpMasks(const aiScene& scene, std::string path, bool honour_opacity, std::vector<std::string>& warnings)
      : scene_(scene),
        honour_opacity_(honour_opacity),
        path_(std::move(path)),
        base_dir_(std::filesystem::path(path_).parent_path()),
        warnings_(warnings),
        builder_(path_) {}

  Material material(unsigned index) {
    if (const auto found = materials_.find(index); found != materials_.end()) return found->second;
    return materials_[index] = resolve(index);
  }

  AlphaMaskBuilder& triangles() { return builder_; }
  AlphaMasks take() { return builder_.take(); }

 private:
  Material resolve(unsigned index) {
    if (index >= scene_.mNumMaterials) return {};
    const aiMaterial& m = *scene_.mMaterials[index];
    float opacity = 1.0f;
    if (honour_opacity_) m.Get(AI_MATKEY_OPACITY, opacity);
    const std::string what = std::string("material '") + m.GetName().C_Str() + "'";
    for (const auto& [type, first_channel] : {std::pair{aiTextureType_OPACITY, true}, {aiTextureType_DIFFUSE, false}}) {
      aiString file;
      aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
      unsigned uv_channel = 0;
      if (m.GetTexture(type, 0, &file, nullptr, &uv_channel, nullptr, nullptr, modes) != AI_SUCCESS) continue;
      if (!first_channel && holds_no_alpha(file)) continue;  // a diffuse map cuts only by its alpha
      const std::string image_name = what + "'s image " + file.C_Str();
      // The structured binding is captured by copy: clang 14 captures none by reference.
      const std::optional<AlphaImage> image =
          alpha_unless_unreadable([&, grey = first_channel] { return alpha_of(file, grey, image_name); }, warnings_);
      if (!image) return {};
      if (!image->has_alpha) continue;
      // Bilinear lookups stay between the texels' least and greatest alpha:
      // where the cutoff does not fall between them, no texel needs looking up.
      const auto [least, most] = std::minmax_element(image->alpha.begin(), image->alpha.end());
      if (opacity * float(*least) / 255.0f >= kMaskCutoff) return constant(1.0f);
      if (opacity * float(*most) / 255.0f < kMaskCutoff) return constant(0.0f);
      const std::uint32_t wrap = wrap_of(modes[0]) | (wrap_of(modes[1]) << 2);
      return {Coverage::Masked, builder_.add_texture(*image, wrap, opacity, kMaskCutoff, image_name), uv_channel};
    }
    return constant(opacity);
  }

  static Material constant(float opacity) {
    Material m;
    m.coverage = opacity < kMaskCutoff ? Coverage::Transparent : Coverage::Opaque;
    return m;
  }

  // Whether the image, embedded or a file, is of a format without alpha (JPEG).
  bool holds_no_alpha(const aiString& file) const {
    if (const aiTexture* embedded = scene_.GetEmbeddedTexture(file.C_Str()))
      return embedded->mHeight == 0 && (embedded->CheckFormat("jpg") || embedded->CheckFormat("jpeg"));
    return cannot_hold_alpha(file.C_Str());
  }

  AlphaImage alpha_of(const aiString& file, bool first_channel, const std::string& what) const {
    const std::string named = path_ + ": " + what;
    return with_image(
        scene_, base_dir_, file, named,
        [&](const unsigned char* bytes, std::size_t size) { return decode_alpha(bytes, size, named, first_channel); },
        [&](const aiTexture& texture) {
          check_alpha_texels(texture.mWidth, texture.mHeight, named);
          const std::size_t texels = std::size_t(texture.mWidth) * texture.mHeight;
          AlphaImage image{int(texture.mWidth), int(texture.mHeight), true, {}};
          image.alpha.reserve(texels);
          for (std::size_t i = 0; i < texels; ++i) image.alpha.push_back(texture.pcData[i].a);
          return image;
        });
  }

  const aiScene& scene_;
  bool honour_opacity_;
  std::string path_;
  std::filesystem::path base_dir_;
  std::vector<std::string>& warnings_;
  AlphaMaskBuilder builder_;
  std::map<unsigned, Material> materials_;
};

glm::mat4 to_glm(const aiMatrix4x4& m) {
  // aiMatrix4x4 is row-major (a1..a4 the first row); glm's constructor takes columns.
  return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4, m.b4, m.c4, m.d4);
}

glm::vec3 to_glm(const aiVector3D& v) { return {v.x, v.y, v.z}; }

// What the node tree puts into the scene: triangles in world space, and
// their alpha masks.
class Gatherer {
 public:
  Gatherer(const aiScene& scene, const std::string& path, const LoadOptions& options, bool honour_opacity,
           std::vector<std::string>& warnings)
      : scene_(scene), path_(path), normals_(options.normals), masks_(scene, path, honour_opacity, warnings) {
    if (options.texcoords) read_materials(options.base_colors, warnings);
  }

  // The nodes numbered in the order they are visited, as LoadedPrimitive::node counts them.
  void node(const aiNode& n, const glm::mat4& parent) {
    const glm::mat4 world = parent * to_glm(n.mTransformation);
    const int number = nodes_++;
    for (unsigned i = 0; i < n.mNumMeshes; ++i) {
      const std::size_t vertices = mesh_.positions.size(), triangles = mesh_.triangles.size();
      const aiMesh& m = *scene_.mMeshes[n.mMeshes[i]];
      mesh(m, world);
      if (uv_sets_.loaded && mesh_.triangles.size() > triangles)
        add_uv_sets(m, LoadedPrimitive{number, int(n.mMeshes[i]), 0, vertices, mesh_.positions.size() - vertices,
                                       triangles, mesh_.triangles.size() - triangles});
    }
    for (unsigned i = 0; i < n.mNumChildren; ++i) node(*n.mChildren[i], world);
  }

  TriangleMesh take_mesh() {
    if (!any_normals_) mesh_.normals.clear();
    return std::move(mesh_);
  }
  AlphaMasks take_masks() { return masks_.take(); }
  // The names of the materials whose triangles were left out as transparent everywhere.
  const std::set<std::string>& transparent() const { return transparent_; }
  UvSets take_uv_sets() { return std::move(uv_sets_); }

 private:
  // Each material's name, the UV channel and wrap modes of its ambient occlusion texture where it has one, and
  // where asked, its base colour.
  void read_materials(bool base_colors, std::vector<std::string>& warnings) {
    uv_sets_.loaded = true;
    for (unsigned i = 0; i < scene_.mNumMaterials; ++i) {
      const aiMaterial& material = *scene_.mMaterials[i];
      MaterialUvs uvs;
      aiString name;
      if (material.Get(AI_MATKEY_NAME, name) == aiReturn_SUCCESS) uvs.name = name.C_Str();
      aiString file;
      unsigned channel = 0;
      aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
      if (material.GetTexture(aiTextureType_AMBIENT_OCCLUSION, 0, &file, nullptr, &channel, nullptr, nullptr, modes) ==
              aiReturn_SUCCESS &&
          channel < unsigned(kMaxUvSets)) {
        uvs.occlusion_texcoord = int(channel);
        uvs.wrap_s = wrap_mode_of_assimp(modes[0]);
        uvs.wrap_t = wrap_mode_of_assimp(modes[1]);
      }
      if (base_colors) uvs.base_color = base_color_of(material, warnings);
      uv_sets_.materials.push_back(std::move(uvs));
    }
  }

  static WrapMode wrap_mode_of_assimp(aiTextureMapMode mode) {
    if (mode == aiTextureMapMode_Mirror) return WrapMode::MirroredRepeat;
    if (mode == aiTextureMapMode_Clamp || mode == aiTextureMapMode_Decal) return WrapMode::ClampToEdge;
    return WrapMode::Repeat;
  }

  // The material's base colour factor (or diffuse colour and opacity), in glTF's range, and its base colour
  // (or diffuse) image; an image that cannot be read adds to `warnings` and is left out.
  BaseColor base_color_of(const aiMaterial& material, std::vector<std::string>& warnings) const {
    BaseColor color;
    aiColor4D base;
    aiColor3D diffuse;
    float opacity = 1.0f;
    if (material.Get(AI_MATKEY_BASE_COLOR, base) == aiReturn_SUCCESS) {
      color.factor = {base.r, base.g, base.b, base.a};
    } else {
      if (material.Get(AI_MATKEY_COLOR_DIFFUSE, diffuse) == aiReturn_SUCCESS)
        color.factor = {diffuse.r, diffuse.g, diffuse.b, 1.0f};
      if (material.Get(AI_MATKEY_OPACITY, opacity) == aiReturn_SUCCESS) color.factor[3] = opacity;
    }
    for (float& f : color.factor) f = std::isfinite(f) ? std::clamp(f, 0.0f, 1.0f) : 1.0f;
    const std::string what = path_ + ": material '" + material.GetName().C_Str() + "''s base colour image ";
    for (const aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
      aiString file;
      unsigned channel = 0;
      aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
      if (material.GetTexture(type, 0, &file, nullptr, &channel, nullptr, nullptr, modes) != aiReturn_SUCCESS) continue;
      try {
        color.image = gltf_image_of(file, what + file.C_Str());
        color.texcoord = int(std::min(channel, unsigned(kMaxUvSets)));  // kMaxUvSets: a set no mesh has
        color.wrap_s = wrap_mode_of_assimp(modes[0]);
        color.wrap_t = wrap_mode_of_assimp(modes[1]);
      } catch (const LoadError& e) {
        warnings.push_back(std::string(e.what()) + "; bake_file writes the material without it");
      }
      break;
    }
    return color;
  }

  // Image `file` as a glTF file holds it (PNG or JPEG).
  std::vector<unsigned char> gltf_image_of(const aiString& file, const std::string& what) const {
    return with_image(
        scene_, std::filesystem::path(path_).parent_path(), file, what,
        [&](const unsigned char* bytes, std::size_t size) { return png_or_jpeg(bytes, size, what); },
        [&](const aiTexture& texture) {
          check_image_texels(texture.mWidth, texture.mHeight, what);
          std::vector<std::uint8_t> rgba;
          rgba.reserve(4 * std::size_t(texture.mWidth) * texture.mHeight);
          for (std::size_t i = 0; i < std::size_t(texture.mWidth) * texture.mHeight; ++i) {
            const aiTexel& t = texture.pcData[i];
            rgba.insert(rgba.end(), {t.r, t.g, t.b, t.a});
          }
          return png_of_rgba(rgba.data(), int(texture.mWidth), int(texture.mHeight));
        });
  }

  // The mesh's UV channels as sets (v down the image, as glTF's: aiProcess_FlipUVs), NaN for the channels
  // it lacks (and each set NaN for the vertices of meshes without it), and its triangles' material.
  void add_uv_sets(const aiMesh& m, const LoadedPrimitive& placed) {
    constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
    for (unsigned channel = 0; channel < unsigned(kMaxUvSets); ++channel) {
      if (!m.HasTextureCoords(channel)) continue;
      if (channel >= uv_sets_.sets.size()) uv_sets_.sets.resize(channel + 1);
      std::vector<glm::vec2>& values = uv_sets_.sets[channel];
      values.resize(placed.first_vertex, glm::vec2(kNone));
      for (unsigned v = 0; v < m.mNumVertices; ++v)
        values.emplace_back(m.mTextureCoords[channel][v].x, m.mTextureCoords[channel][v].y);
    }
    for (std::vector<glm::vec2>& values : uv_sets_.sets) values.resize(mesh_.positions.size(), glm::vec2(kNone));
    uv_sets_.triangle_materials.insert(uv_sets_.triangle_materials.end(), placed.triangle_count,
                                       std::int32_t(m.mMaterialIndex));
    uv_sets_.primitives.push_back(placed);
  }

  void mesh(const aiMesh& m, const glm::mat4& world) {
    if (!(m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) return;  // points and lines, sorted apart
    const AssimpMasks::Material material = masks_.material(m.mMaterialIndex);
    if (material.coverage == AssimpMasks::Coverage::Transparent) {  // cut away everywhere: no triangles
      transparent_.insert(m.mMaterialIndex < scene_.mNumMaterials
                              ? scene_.mMaterials[m.mMaterialIndex]->GetName().C_Str()
                              : std::to_string(m.mMaterialIndex));
      return;
    }
    const auto base = std::uint32_t(mesh_.positions.size());
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(world)));
    const bool with_normals = normals_ && m.HasNormals();
    any_normals_ = any_normals_ || with_normals;
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
      mesh_.positions.push_back(glm::vec3(world * glm::vec4(to_glm(m.mVertices[v]), 1.0f)));
      glm::vec3 normal(0.0f);  // zero: "no normal here" (TriangleMesh)
      if (with_normals) {
        const glm::vec3 n = normal_matrix * to_glm(m.mNormals[v]);
        const float length = glm::length(n);
        if (std::isfinite(length) && length > 0.0f) normal = n / length;
      }
      mesh_.normals.push_back(normal);
    }
    std::vector<std::uint32_t> corners;  // the mesh's own vertex indices, for its masks
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices != 3) continue;
      mesh_.triangles.push_back(glm::uvec3(face.mIndices[0], face.mIndices[1], face.mIndices[2]) + base);
      corners.insert(corners.end(), face.mIndices, face.mIndices + 3);
    }
    if (material.coverage == AssimpMasks::Coverage::Masked)
      masks_.triangles().add_masked(corners, texcoords(m, material.uv_channel), material.texture);
    else
      masks_.triangles().add_opaque(corners.size() / 3);
  }

  // UV set `channel` of the mesh, 2 floats per vertex, v down the image (aiProcess_FlipUVs).
  std::vector<float> texcoords(const aiMesh& m, unsigned channel) const {
    if (channel >= AI_MAX_NUMBER_OF_TEXTURECOORDS || !m.HasTextureCoords(channel))
      throw LoadError(path_ + ": mesh '" + m.mName.C_Str() + "' has an alpha mask but no texture coordinates " +
                      std::to_string(channel) + " to look it up with");
    std::vector<float> uv;
    uv.reserve(2 * std::size_t(m.mNumVertices));
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
      uv.push_back(m.mTextureCoords[channel][v].x);
      uv.push_back(m.mTextureCoords[channel][v].y);
    }
    return uv;
  }

  const aiScene& scene_;
  const std::string& path_;
  bool normals_, any_normals_ = false;
  int nodes_ = 0;
  TriangleMesh mesh_;
  AssimpMasks masks_;
  std::set<std::string> transparent_;
  UvSets uv_sets_;
};

// The world transform of the node named `name`, where there is one.
std::optional<glm::mat4> world_of(const aiNode& n, const aiString& name, const glm::mat4& parent) {
  const glm::mat4 world = parent * to_glm(n.mTransformation);
  if (n.mName == name) return world;
  for (unsigned i = 0; i < n.mNumChildren; ++i)
    if (auto found = world_of(*n.mChildren[i], name, world)) return found;
  return std::nullopt;
}

// The file's first perspective camera with a known field of view, placed by
// its node. Assimp 5.2's loaders store the full horizontal angle (not the
// half its header describes: assimp issues 2256 and 5691), and the aspect
// ratio where the file gives one; without it the vertical angle is unknown.
std::optional<Camera> first_camera(const aiScene& scene, const std::string& path, std::vector<std::string>& warnings) {
  for (unsigned i = 0; i < scene.mNumCameras; ++i) {
    const aiCamera& c = *scene.mCameras[i];
    const std::string name = path + ": camera '" + c.mName.C_Str() + "'";
    if (c.mOrthographicWidth > 0.0f) {
      warnings.push_back(name + " is orthographic; only perspective cameras are read (SPEC 3.1)");
      continue;
    }
    if (!(c.mAspect > 0.0f)) {
      warnings.push_back(name +
                         " skipped: Assimp gives no aspect ratio for it, so its vertical field of view is "
                         "unknown; pass camera=mbao.Camera(...) or a camera.json");
      continue;
    }
    const glm::mat4 world = world_of(*scene.mRootNode, c.mName, glm::mat4(1.0f)).value_or(glm::mat4(1.0f));
    const glm::vec3 eye(world * glm::vec4(to_glm(c.mPosition), 1.0f));
    const glm::vec3 forward(world * glm::vec4(to_glm(c.mLookAt), 0.0f)), up(world * glm::vec4(to_glm(c.mUp), 0.0f));
    const float vfov = 2.0f * std::atan(std::tan(0.5f * c.mHorizontalFOV) / c.mAspect);
    return Camera{eye, eye + forward, up, glm::degrees(vfov), std::nullopt};
  }
  return std::nullopt;
}

std::size_t dropped_primitives(const aiScene& scene) {
  std::size_t count = 0;
  for (unsigned i = 0; i < scene.mNumMeshes; ++i)
    if (!(scene.mMeshes[i]->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) count += scene.mMeshes[i]->mNumFaces;
  return count;
}

// The scene's triangles, masks, camera and UV sets, and in `transparent` the
// materials left out as cut away everywhere; where `honour_opacity` is false,
// every material's opacity is taken as 1.
ImportedScene gathered(const aiScene& scene, const std::string& path, const LoadOptions& options, bool honour_opacity,
                       std::set<std::string>& transparent) {
  std::vector<std::string> warnings;
  Gatherer gatherer(scene, path, options, honour_opacity, warnings);
  gatherer.node(*scene.mRootNode, glm::mat4(1.0f));
  if (const std::size_t dropped = dropped_primitives(scene))
    warnings.push_back(path + ": " + std::to_string(dropped) + " points and lines skipped; only triangles render");
  std::optional<Camera> camera = first_camera(scene, path, warnings);
  transparent = gatherer.transparent();
  return {gatherer.take_mesh(), gatherer.take_masks(), camera, std::move(warnings), gatherer.take_uv_sets()};
}

std::string joined(const std::set<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "'" : ", '") + name + "'";
  return text;
}

// A scene all of whose triangles are in materials cut away everywhere
// (`transparent`; SPEC 3.2), read again with every opacity taken as 1, with a
// warning: Collada exporters often write transparency the other way round from
// what the format means, and a scene of nothing helps no one. Where the
// materials' images still cut it all away, a LoadError naming them.
ImportedScene opaque_instead(const aiScene& scene, const std::string& path, const LoadOptions& options,
                             const std::set<std::string>& transparent) {
  std::set<std::string> still;
  ImportedScene s = gathered(scene, path, options, false, still);
  if (s.mesh.triangles.empty())
    throw LoadError(path + ": no triangles in it are left: the alpha of their materials' images (" + joined(still) +
                    ") is below 0.5 everywhere (SPEC 3.2)");
  std::set<std::string> by_opacity;
  std::set_difference(transparent.begin(), transparent.end(), still.begin(), still.end(),
                      std::inserter(by_opacity, by_opacity.end()));
  s.warnings.push_back(path + ": every triangle is in a material of opacity below 0.5 (" + joined(by_opacity) +
                       "), which would leave nothing; their opacity is taken as 1 (a Collada exporter may have "
                       "written its transparency the other way round)");
  return s;
}

// Why a scene with meshes is flagged incomplete: LightWave's scene loader flags
// one without materials; the flag carries no reason of its own.
std::string what_is_missing(const aiScene& scene) {
  return scene.mNumMaterials == 0 ? "it has no materials" : "the importer gives no reason";
}

}  // namespace

ImportedScene scene_from_assimp(const aiScene& scene, const std::string& path, const LoadOptions& options) {
  if (!scene.mRootNode) throw LoadError(path + ": Assimp read no node tree from it");
  std::set<std::string> transparent;
  ImportedScene s = gathered(scene, path, options, true, transparent);
  if (s.mesh.triangles.empty() && scene.mNumMeshes == 0)
    throw LoadError(path + ": no meshes in it (Assimp found no geometry it could read)");
  if (s.mesh.triangles.empty() && transparent.empty()) throw LoadError(path + ": no triangles in it");
  if (s.mesh.triangles.empty()) s = opaque_instead(scene, path, options, transparent);
  if (scene.mFlags & AI_SCENE_FLAGS_INCOMPLETE)
    s.warnings.push_back(path + ": Assimp flagged the scene incomplete (" + what_is_missing(scene) +
                         "); its triangles are loaded");
  return s;
}

}  // namespace mbao
