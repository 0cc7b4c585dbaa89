#include "scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>
#include <limits>
#include <unordered_map>

#include "core/error.h"
#include "scene/gltf_accessor_reader.h"
#include "scene/gltf_alpha_masks.h"
#include "scene/gltf_draco.h"
#include "scene/gltf_tinygltf_workarounds.h"
#include "scene/gltf_container.h"
#include "scene/gltf_files.h"

namespace mbao {
namespace {

constexpr std::size_t kMaxVertices = std::size_t(std::numeric_limits<std::uint32_t>::max()) + 1;
// TEXCOORD_0 .. TEXCOORD_7: more than any exporter writes, few enough that a
// file cannot make the loader keep hundreds of empty sets.

glm::dmat4 local_transform(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());
  glm::dmat4 m(1.0);
  if (node.translation.size() == 3) m = glm::translate(m, glm::make_vec3(node.translation.data()));
  if (node.rotation.size() == 4)
    m *= glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
  if (node.scale.size() == 3) m = glm::scale(m, glm::make_vec3(node.scale.data()));
  return m;
}

class SceneAssembler {
 public:
  SceneAssembler(const tinygltf::Model& model, std::string path, const std::string& base_dir,
                 const LoadOptions& options, const std::string& parser_warnings)
      : model_(model),
        path_(std::move(path)),
        options_(options),
        accessors_(model, path_),
        masks_(model, accessors_, path_, base_dir, warnings_) {
    if (!parser_warnings.empty()) warnings_.push_back(path_ + ": " + parser_warnings);
  }

  std::shared_ptr<Scene> assemble() {
    const int scene_index = pick_scene();
    place_nodes(model_.scenes[std::size_t(scene_index)].nodes);
    reserve();
    if (options_.texcoords) read_materials();
    for (const Instance& instance : instances_) {
      const std::size_t vertices = mesh_.positions.size(), triangles = mesh_.triangles.size();
      add_primitive(*instance.primitive, instance.world, instance.what);
      if (options_.texcoords && mesh_.triangles.size() > triangles)
        uv_sets_.primitives.push_back({instance.node, instance.mesh, instance.index, vertices,
                                       mesh_.positions.size() - vertices, triangles,
                                       mesh_.triangles.size() - triangles});
    }
    if (mesh_.triangles.empty()) throw LoadError(path_ + ": the default scene has no triangles");
    return std::make_shared<Scene>(std::move(mesh_), path_, camera_, std::move(warnings_), masks_.take(),
                                   std::move(uv_sets_));
  }

 private:
  int pick_scene() {
    if (model_.scenes.empty()) throw LoadError(path_ + ": the file defines no scene");
    if (model_.defaultScene >= 0) {
      if (std::size_t(model_.defaultScene) >= model_.scenes.size())
        throw LoadError(path_ + ": default scene " + std::to_string(model_.defaultScene) + " does not exist");
      return model_.defaultScene;
    }
    if (model_.scenes.size() > 1) warnings_.push_back(path_ + ": no default scene is set; using scene 0");
    return 0;
  }

  // The default scene's node trees, depth first with children in order (the
  // order triangles and the first camera are taken in). Iterative, so a deep
  // hierarchy cannot overflow the stack. Each node is placed once: glTF node
  // hierarchies are disjoint trees, and a node reached twice (a cycle, or
  // shared parents) could multiply the work exponentially.
  void place_nodes(const std::vector<int>& roots) {
    struct Pending {
      int index;
      int parent;  // -1: a scene root
      glm::dmat4 parent_world;
    };
    std::vector<Pending> pending;
    for (auto root = roots.rbegin(); root != roots.rend(); ++root) pending.push_back({*root, -1, glm::dmat4(1.0)});
    while (!pending.empty()) {
      const Pending next = pending.back();
      pending.pop_back();
      place(next.index, next.parent);
      const tinygltf::Node& node = model_.nodes[std::size_t(next.index)];
      const glm::dmat4 world = next.parent_world * local_transform(node);
      const std::string name = "node " + std::to_string(next.index);
      if (node.mesh >= 0) add_mesh(node.mesh, world, next.index, name);
      if (node.camera >= 0 && !camera_) take_camera(node.camera, world, name);
      for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
        pending.push_back({*child, next.index, world});
    }
  }

  // Records `parent` (-1: the scene) as the parent of node `index`, which must
  // exist and not be placed yet.
  void place(int index, int parent) {
    const std::string from = parent < 0 ? "the scene" : "node " + std::to_string(parent);
    const std::string name = "node " + std::to_string(index);
    if (index < 0 || std::size_t(index) >= model_.nodes.size())
      throw LoadError(path_ + ": " + from + " refers to " + name + ", which does not exist");
    const auto placed = parents_.find(index);
    if (placed == parents_.end()) {
      parents_.emplace(index, parent);
      return;
    }
    for (int ancestor = parent; ancestor >= 0; ancestor = parents_.at(ancestor))
      if (ancestor == index) throw LoadError(path_ + ": " + name + " is its own ancestor (the node graph has a cycle)");
    if (placed->second == parent) throw LoadError(path_ + ": " + from + " lists " + name + " twice");
    const std::string first = placed->second < 0 ? "the scene" : "node " + std::to_string(placed->second);
    throw LoadError(path_ + ": " + name + " is reached twice, from " + first + " and from " + from +
                    " (glTF node hierarchies must be trees)");
  }

  void take_camera(int index, const glm::dmat4& world, const std::string& node) {
    if (std::size_t(index) >= model_.cameras.size())
      throw LoadError(path_ + ": " + node + " refers to camera " + std::to_string(index) + ", which does not exist");
    const tinygltf::Camera& source = model_.cameras[std::size_t(index)];
    if (source.type != "perspective") return;
    Camera camera;
    camera.eye = glm::vec3(world * glm::dvec4(0, 0, 0, 1));
    camera.target = camera.eye + glm::normalize(glm::vec3(world * glm::dvec4(0, 0, -1, 0)));
    camera.up = glm::normalize(glm::vec3(world * glm::dvec4(0, 1, 0, 0)));
    camera.vfov_deg = float(glm::degrees(source.perspective.yfov));
    camera.max_distance = suggested_radius(source, index);
    try {
      camera.validate();
      camera_ = camera;
    } catch (const std::invalid_argument& e) {
      warnings_.push_back(path_ + ": camera " + std::to_string(index) + " ignored (" + e.what() + ")");
    }
  }

  // The AO radius a camera's extras suggest ({"max_distance": d}, world units; SPEC 1), as camera.json's.
  // A value that is not a positive finite number is left out, with a warning.
  std::optional<float> suggested_radius(const tinygltf::Camera& source, int index) {
    if (!source.extras.IsObject() || !source.extras.Has("max_distance")) return std::nullopt;
    const tinygltf::Value& value = source.extras.Get("max_distance");
    const double radius = value.IsNumber() ? value.GetNumberAsDouble() : std::nan("");
    if (radius > 0.0 && radius <= double(std::numeric_limits<float>::max())) return float(radius);
    warnings_.push_back(path_ + ": camera " + std::to_string(index) +
                        " extras.max_distance ignored (a radius must be a number > 0)");
    return std::nullopt;
  }

  void add_mesh(int index, const glm::dmat4& world, int node_index, const std::string& node) {
    if (std::size_t(index) >= model_.meshes.size())
      throw LoadError(path_ + ": " + node + " refers to mesh " + std::to_string(index) + ", which does not exist");
    const tinygltf::Mesh& mesh = model_.meshes[std::size_t(index)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
      instances_.push_back({&mesh.primitives[p], world,
                            "mesh " + std::to_string(index) + " primitive " + std::to_string(p), node_index, index,
                            int(p)});
  }

  // Room for every instance's vertices and triangles up front, so the arrays
  // are not copied as they grow. The accessors' declared counts are checked
  // when read; here they only size the arrays, capped by what the buffers hold.
  void reserve() {
    std::size_t vertices = 0, indices = 0, buffer_bytes = 0;
    for (const tinygltf::Buffer& buffer : model_.buffers) buffer_bytes += buffer.data.size();
    const auto declared = [&](int accessor) {
      return accessor >= 0 && std::size_t(accessor) < model_.accessors.size()
                 ? model_.accessors[std::size_t(accessor)].count
                 : 0;
    };
    std::size_t masked_indices = 0;
    for (const Instance& instance : instances_) {
      const auto position = instance.primitive->attributes.find("POSITION");
      if (position == instance.primitive->attributes.end()) continue;
      vertices += declared(position->second);
      const std::size_t count =
          instance.primitive->indices >= 0 ? declared(instance.primitive->indices) : declared(position->second);
      indices += count;
      if (masks_.material(instance.primitive->material).coverage == GltfAlphaMasks::Coverage::Masked)
        masked_indices += count;
    }
    mesh_.positions.reserve(std::min(vertices, buffer_bytes / 12));
    mesh_.triangles.reserve(std::min(indices / 3, buffer_bytes / 3));
    masks_.triangles().reserve(std::min(masked_indices / 3, buffer_bytes / 3), std::min(indices / 3, buffer_bytes / 3));
  }

  void add_primitive(const tinygltf::Primitive& primitive, const glm::dmat4& world, const std::string& what) {
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      warnings_.push_back(path_ + ": " + what + " skipped: mode " + std::to_string(mode) +
                          " is points or lines, not triangles");
      return;
    }
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) {
      warnings_.push_back(path_ + ": " + what + " skipped: it has no POSITION attribute");
      return;
    }
    const GltfAlphaMasks::Material material = masks_.material(primitive.material);
    if (material.coverage == GltfAlphaMasks::Coverage::Transparent) return;  // cut away everywhere: no triangles
    if (is_draco_compressed(primitive)) decode_draco_primitive(primitive, accessors_, what);

    const std::vector<float> positions = accessors_.quantized(position->second, TINYGLTF_TYPE_VEC3, what + " POSITION");
    const std::size_t vertex_count = positions.size() / 3;
    if (vertex_count > kMaxVertices - mesh_.positions.size())
      throw LoadError(path_ + ": " + what + " brings the default scene to more than " + std::to_string(kMaxVertices) +
                      " vertices, more than 32-bit vertex indices reach");
    const std::vector<std::uint32_t> indices = triangle_indices(primitive, mode, vertex_count, what);
    const auto base = std::uint32_t(mesh_.positions.size());
    const bool in_place = world == glm::dmat4(1.0);  // the usual case: no transform to apply
    for (std::size_t v = 0; v < vertex_count; ++v) {
      const glm::vec3 local(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
      const glm::vec3 p = in_place ? local : glm::vec3(world * glm::dvec4(local, 1.0));
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw LoadError(path_ + ": " + what + " vertex " + std::to_string(v) +
                        " is not finite in world space (its POSITION or a node transform is not finite or too large)");
      mesh_.positions.push_back(p);
    }
    for (std::size_t t = 0; t < indices.size(); t += 3)
      mesh_.triangles.push_back({base + indices[t], base + indices[t + 1], base + indices[t + 2]});
    if (options_.normals) add_normals(primitive, world, what, vertex_count);
    if (options_.texcoords) add_uv_sets(primitive, what, vertex_count, indices.size() / 3);
    if (material.coverage == GltfAlphaMasks::Coverage::Masked)
      masks_.triangles().add_masked(
          indices, material.transformed(texcoords(primitive, material.texcoord_set, vertex_count, what)),
          material.texture);
    else
      masks_.triangles().add_opaque(indices.size() / 3);
  }

  // The primitive's triangles as a list of vertex indices, three a triangle,
  // checked against its vertex count: a strip's or a fan's as glTF orders
  // their corners (glTF 2.0, 3.7.2.1), so that they face as the file means.
  std::vector<std::uint32_t> triangle_indices(const tinygltf::Primitive& primitive, int mode, std::size_t vertex_count,
                                              const std::string& what) const {
    std::vector<std::uint32_t> indices;
    if (primitive.indices >= 0) {
      indices = accessors_.indices(primitive.indices, what + " indices");
    } else {
      indices.resize(vertex_count);
      for (std::size_t i = 0; i < vertex_count; ++i) indices[i] = std::uint32_t(i);
    }
    if (mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0)
      throw LoadError(path_ + ": " + what + " has " + std::to_string(indices.size()) + " indices, not a multiple of 3");
    for (std::uint32_t i : indices)
      if (i >= vertex_count)
        throw LoadError(path_ + ": " + what + " uses vertex " + std::to_string(i) + ", but POSITION has only " +
                        std::to_string(vertex_count));
    if (mode == TINYGLTF_MODE_TRIANGLES) return indices;
    return mode == TINYGLTF_MODE_TRIANGLE_STRIP ? strip_triangles(indices) : fan_triangles(indices);
  }

  static std::vector<std::uint32_t> strip_triangles(const std::vector<std::uint32_t>& v) {
    std::vector<std::uint32_t> list;
    for (std::size_t i = 0; i + 2 < v.size(); ++i) list.insert(list.end(), {v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]});
    return list;
  }

  static std::vector<std::uint32_t> fan_triangles(const std::vector<std::uint32_t>& v) {
    std::vector<std::uint32_t> list;
    for (std::size_t i = 0; i + 2 < v.size(); ++i) list.insert(list.end(), {v[i + 1], v[i + 2], v[0]});
    return list;
  }

  std::vector<float> texcoords(const tinygltf::Primitive& primitive, int set, std::size_t vertex_count,
                               const std::string& what) const {
    const std::string name = "TEXCOORD_" + std::to_string(set);
    const auto attribute = primitive.attributes.find(name);
    if (attribute == primitive.attributes.end())
      throw LoadError(path_ + ": " + what + " has an alpha-masked material but no " + name + " attribute");
    std::vector<float> uv = accessors_.texcoords(attribute->second, what + " " + name);
    if (uv.size() / 2 != vertex_count)
      throw LoadError(path_ + ": " + what + " has " + std::to_string(uv.size() / 2) + " " + name + " values for " +
                      std::to_string(vertex_count) + " positions");
    return uv;
  }

  // Each material's name and occlusion texture: the UV set and wrap modes a texture bake takes by default.
  void read_materials() {
    uv_sets_.loaded = true;
    for (std::size_t m = 0; m < model_.materials.size(); ++m) {
      const tinygltf::Material& material = model_.materials[m];
      MaterialUvs uvs;
      uvs.name = material.name;
      const tinygltf::OcclusionTextureInfo& occlusion = material.occlusionTexture;
      if (occlusion.index >= 0) {
        const std::string what = "material " + std::to_string(m) + " occlusionTexture";
        if (std::size_t(occlusion.index) >= model_.textures.size())
          throw LoadError(path_ + ": " + what + " uses texture " + std::to_string(occlusion.index) +
                          ", which does not exist");
        if (occlusion.texCoord < 0 || occlusion.texCoord >= kMaxUvSets)
          throw LoadError(path_ + ": " + what + " has texCoord " + std::to_string(occlusion.texCoord) +
                          "; mbao reads TEXCOORD_0 to TEXCOORD_" + std::to_string(kMaxUvSets - 1));
        uvs.occlusion_texcoord = occlusion.texCoord;
        const int sampler = model_.textures[std::size_t(occlusion.index)].sampler;
        if (sampler >= 0 && std::size_t(sampler) >= model_.samplers.size())
          throw LoadError(path_ + ": texture " + std::to_string(occlusion.index) + " uses sampler " +
                          std::to_string(sampler) + ", which does not exist");
        if (sampler >= 0) {
          uvs.wrap_s = wrap_mode_of_gltf(model_.samplers[std::size_t(sampler)].wrapS);
          uvs.wrap_t = wrap_mode_of_gltf(model_.samplers[std::size_t(sampler)].wrapT);
        }
      }
      uv_sets_.materials.push_back(uvs);
    }
  }

  // The primitive's UV sets, NaN for the sets it does not have (and each set
  // NaN for the vertices of primitives without it), and its triangles' material.
  void add_uv_sets(const tinygltf::Primitive& primitive, const std::string& what, std::size_t vertex_count,
                   std::size_t triangle_count) {
    const std::size_t first = mesh_.positions.size() - vertex_count;
    constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
    for (const auto& [name, accessor] : primitive.attributes) {
      const int set = uv_set_number(name);
      if (set < 0) continue;
      if (set >= kMaxUvSets) {
        warnings_.push_back(path_ + ": " + what + " " + name + " skipped: mbao reads TEXCOORD_0 to TEXCOORD_" +
                            std::to_string(kMaxUvSets - 1));
        continue;
      }
      const std::vector<float> uv = texcoords(primitive, set, vertex_count, what);
      if (std::size_t(set) >= uv_sets_.sets.size()) uv_sets_.sets.resize(std::size_t(set) + 1);
      std::vector<glm::vec2>& values = uv_sets_.sets[std::size_t(set)];
      values.resize(first, glm::vec2(kNone));
      for (std::size_t v = 0; v < vertex_count; ++v) values.emplace_back(uv[2 * v], uv[2 * v + 1]);
    }
    for (std::vector<glm::vec2>& values : uv_sets_.sets) values.resize(mesh_.positions.size(), glm::vec2(kNone));
    uv_sets_.triangle_materials.insert(uv_sets_.triangle_materials.end(), triangle_count,
                                       primitive.material >= 0 ? primitive.material : -1);
  }

  // n of an attribute named TEXCOORD_n, else -1.
  static int uv_set_number(const std::string& name) {
    const std::string prefix = "TEXCOORD_";
    if (name.rfind(prefix, 0) != 0 || name.size() == prefix.size() || name.size() > prefix.size() + 4) return -1;
    if (name[prefix.size()] == '0' && name.size() > prefix.size() + 1) return -1;  // TEXCOORD_01 is not set 1
    int n = 0;
    for (std::size_t i = prefix.size(); i < name.size(); ++i) {
      if (!std::isdigit(static_cast<unsigned char>(name[i]))) return -1;
      n = 10 * n + (name[i] - '0');
    }
    return n;
  }

  // Normals are kept per vertex; vertices of primitives without normals get
  // zero, which the kernels read as "use the geometric normal".
  void add_normals(const tinygltf::Primitive& primitive, const glm::dmat4& world, const std::string& what,
                   std::size_t vertex_count) {
    const auto normal = primitive.attributes.find("NORMAL");
    if (normal == primitive.attributes.end()) {
      if (mesh_.has_normals()) mesh_.normals.resize(mesh_.positions.size(), glm::vec3(0.0f));
      return;
    }
    const std::vector<float> normals = accessors_.quantized(normal->second, TINYGLTF_TYPE_VEC3, what + " NORMAL");
    if (normals.size() / 3 != vertex_count)
      throw LoadError(path_ + ": " + what + " has " + std::to_string(normals.size() / 3) + " normals for " +
                      std::to_string(vertex_count) + " positions");
    if (!mesh_.has_normals()) mesh_.normals.reserve(mesh_.positions.capacity());
    mesh_.normals.resize(mesh_.positions.size() - vertex_count, glm::vec3(0.0f));
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
    for (std::size_t v = 0; v < vertex_count; ++v) {
      const glm::dvec3 n = normal_matrix * glm::dvec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
      const double length = glm::length(n);
      mesh_.normals.push_back(length > 0.0 && std::isfinite(length) ? glm::vec3(n / length) : glm::vec3(0.0f));
    }
  }

  // A mesh primitive where the default scene places it.
  struct Instance {
    const tinygltf::Primitive* primitive;
    glm::dmat4 world;
    std::string what;       // "mesh M primitive P", for messages
    int node, mesh, index;  // the node that places it, its mesh, and its index in the mesh
  };

  const tinygltf::Model& model_;
  std::string path_;
  LoadOptions options_;
  std::vector<Instance> instances_;
  std::vector<std::string> warnings_;
  AccessorReader accessors_;
  GltfAlphaMasks masks_;
  TriangleMesh mesh_;
  std::optional<Camera> camera_;
  UvSets uv_sets_;
  std::unordered_map<int, int> parents_;  // node -> its parent, -1 for a scene root
};

// glTF 2.0 and nothing else: glTF 1.0 files parse into a different, wrong
// model, and a required extension changes what the data means (Draco
// compressed geometry would read as zeros, for instance).
void check_supported(const tinygltf::Model& model, const std::string& name) {
  const tinygltf::Asset& asset = model.asset;
  if (asset.version.rfind("2.", 0) != 0 || !(asset.minVersion.empty() || asset.minVersion == "2.0"))
    throw LoadError(name + ": asset.version is \"" + asset.version + "\"" +
                    (asset.minVersion.empty() ? "" : " (minVersion \"" + asset.minVersion + "\")") +
                    "; only glTF 2.0 is supported");
  for (const std::string& extension : model.extensionsRequired)
    if (extension != "KHR_mesh_quantization" && extension != "KHR_draco_mesh_compression" &&
        extension != "EXT_meshopt_compression" && extension != "KHR_texture_transform")
      throw LoadError(name + ": extensionsRequired lists " + extension +
                      ", which mbao does not read; of the extensions a file may require, it reads "
                      "KHR_mesh_quantization, KHR_draco_mesh_compression, EXT_meshopt_compression and "
                      "KHR_texture_transform (on mask textures)");
}

// tinygltf quotes in full a data URI it cannot decode, which may be megabytes
// of base64: its media type and the payload's first characters are kept.
std::string abbreviate_data_uris(const std::string& message) {
  constexpr std::size_t kPayloadKept = 16;
  std::string shortened;
  std::size_t copied_to = 0;
  for (std::size_t uri = message.find("data:"); uri != std::string::npos; uri = message.find("data:", copied_to)) {
    const std::size_t end = std::min(message.find_first_of(" \t\r\n'\"", uri), message.size());
    const std::size_t payload = message.find(',', uri) + 1;  // 0 when there is no comma
    const std::size_t kept_to = payload + kPayloadKept;
    if (payload == 0 || payload > end || end < kept_to + 32) {  // short enough to quote
      shortened.append(message, copied_to, end - copied_to);
    } else {
      shortened.append(message, copied_to, kept_to - copied_to);
      shortened += "... (" + std::to_string(end - uri) + " characters)";
    }
    copied_to = end;
  }
  return shortened.append(message, copied_to);
}

}  // namespace

std::shared_ptr<Scene> load_gltf(const std::string& path, const LoadOptions& options) {
  const std::vector<unsigned char> bytes = read_regular_file(path, "");
  return load_gltf_from_memory(bytes.data(), bytes.size(), path, std::filesystem::path(path).parent_path().string(),
                               options);
}

std::shared_ptr<Scene> load_gltf_from_memory(const unsigned char* bytes, std::size_t size, const std::string& name,
                                             const std::string& base_dir, const LoadOptions& options) {
  if (size > std::numeric_limits<unsigned int>::max())  // tinygltf takes the size as an unsigned int
    throw LoadError(name + ": " + std::to_string(size) + " bytes is more than the 4 GiB a glTF file may have");
  const GltfContainer container = check_gltf_container(bytes, size, name);
  const std::vector<unsigned char> readable = tinygltf_readable(bytes, size, container == GltfContainer::Glb);
  if (!readable.empty()) {
    bytes = readable.data();
    size = readable.size();
  }
  tinygltf::TinyGLTF loader;
  // Images are not decoded here; GltfAlphaMasks decodes the alpha of the few that masks use.
  loader.SetImageLoader(keep_data_uri_images, nullptr);
  loader.SetFsCallbacks(regular_file_callbacks());
  tinygltf::Model model;
  std::string error, warning;
  const auto length = static_cast<unsigned int>(size);
  const bool ok = container == GltfContainer::Glb
                      ? loader.LoadBinaryFromMemory(&model, &error, &warning, bytes, length, base_dir)
                      : loader.LoadASCIIFromString(&model, &error, &warning, reinterpret_cast<const char*>(bytes),
                                                   length, base_dir);
  if (!ok) {
    error.erase(error.find_last_not_of(" \t\r\n") + 1);  // tinygltf ends each error with a newline
    throw LoadError(
        name + ": not a readable glTF 2.0 file: " + (error.empty() ? "unknown error" : abbreviate_data_uris(error)));
  }
  check_supported(model, name);
  return SceneAssembler(model, name, base_dir, options, abbreviate_data_uris(warning)).assemble();
}

}  // namespace mbao
