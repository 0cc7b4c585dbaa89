#include "scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>
#include <limits>
#include <set>

#include "core/error.h"

namespace mbao {
namespace {

// Images carry nothing AO needs: leave them undecoded.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                void*) {
  return true;
}

std::size_t component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

std::string component_name(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    default: return "component type " + std::to_string(component_type);
  }
}

// Reads the elements of one accessor, bounds-checked, sparse substitution
// applied. Every element comes out as `components` values of type T.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, std::string path) : model_(model), path_(std::move(path)) {}

  std::vector<float> floats(int index, int type, const std::string& role) const {
    const tinygltf::Accessor& accessor = get(index, role);
    expect_type(accessor, index, type, role);
    if (accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(index, role, "has " + component_name(accessor.componentType) + " components; only FLOAT is supported");
    return read<float>(accessor, index, role);
  }

  std::vector<std::uint32_t> indices(int index, const std::string& role) const {
    const tinygltf::Accessor& accessor = get(index, role);
    expect_type(accessor, index, TINYGLTF_TYPE_SCALAR, role);
    switch (accessor.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return read<std::uint32_t>(accessor, index, role);
      default:
        fail(index, role,
             "has " + component_name(accessor.componentType) +
                 " components; indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    }
  }

  std::size_t count(int index, const std::string& role) const { return get(index, role).count; }

 private:
  [[noreturn]] void fail(int index, const std::string& role, const std::string& problem) const {
    throw LoadError(path_ + ": accessor " + std::to_string(index) + " (" + role + ") " + problem);
  }

  const tinygltf::Accessor& get(int index, const std::string& role) const {
    if (index < 0 || std::size_t(index) >= model_.accessors.size())
      throw LoadError(path_ + ": " + role + " refers to accessor " + std::to_string(index) + ", but the file has " +
                      std::to_string(model_.accessors.size()));
    return model_.accessors[std::size_t(index)];
  }

  void expect_type(const tinygltf::Accessor& accessor, int index, int type, const std::string& role) const {
    if (accessor.type != type)
      fail(index, role, "has " + std::to_string(tinygltf::GetNumComponentsInType(std::uint32_t(accessor.type))) +
                            " components per element, expected " +
                            std::to_string(tinygltf::GetNumComponentsInType(std::uint32_t(type))));
  }

  // The bytes [offset, offset + stride * (count - 1) + element) of a buffer
  // view, checked against the view and its buffer.
  const unsigned char* view_bytes(int view_index, std::size_t offset, std::size_t stride, std::size_t count,
                                  std::size_t element, int accessor_index, const std::string& role) const {
    if (view_index < 0 || std::size_t(view_index) >= model_.bufferViews.size())
      fail(accessor_index, role, "refers to bufferView " + std::to_string(view_index) + ", which does not exist");
    const tinygltf::BufferView& view = model_.bufferViews[std::size_t(view_index)];
    if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
      fail(accessor_index, role, "uses bufferView " + std::to_string(view_index) + " of missing buffer " +
                                     std::to_string(view.buffer));
    const std::vector<unsigned char>& buffer = model_.buffers[std::size_t(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
      fail(accessor_index, role, "uses bufferView " + std::to_string(view_index) + ", which runs past the end of buffer " +
                                     std::to_string(view.buffer));
    const std::size_t max = std::numeric_limits<std::size_t>::max();
    const bool overflows = count > 0 && (count - 1 > (max - element) / std::max<std::size_t>(stride, 1));
    const std::size_t span = count == 0 ? 0 : (count - 1) * stride + element;
    if (overflows || offset > view.byteLength || span > view.byteLength - offset)
      fail(accessor_index, role, "declares " + std::to_string(count) + " elements, more than bufferView " +
                                     std::to_string(view_index) + " holds");
    return buffer.data() + view.byteOffset + offset;
  }

  template <typename T>
  static T component(const unsigned char* p, int component_type) {
    switch (component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return T(*p);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return T(v);
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return T(v);
      }
      default: {
        float v;
        std::memcpy(&v, p, 4);
        return T(v);
      }
    }
  }

  template <typename T>
  std::vector<T> read(const tinygltf::Accessor& accessor, int index, const std::string& role) const {
    const std::size_t components = std::size_t(tinygltf::GetNumComponentsInType(std::uint32_t(accessor.type)));
    const std::size_t size = component_size(accessor.componentType);
    const std::size_t element = components * size;
    std::vector<T> values(accessor.count * components, T(0));  // a missing bufferView means zeros
    if (accessor.bufferView >= 0) {
      if (std::size_t(accessor.bufferView) >= model_.bufferViews.size())
        fail(index, role, "refers to bufferView " + std::to_string(accessor.bufferView) + ", which does not exist");
      const tinygltf::BufferView& view = model_.bufferViews[std::size_t(accessor.bufferView)];
      const std::size_t stride = view.byteStride ? view.byteStride : element;
      const unsigned char* bytes =
          view_bytes(accessor.bufferView, accessor.byteOffset, stride, accessor.count, element, index, role);
      for (std::size_t i = 0; i < accessor.count; ++i)
        for (std::size_t c = 0; c < components; ++c)
          values[i * components + c] = component<T>(bytes + i * stride + c * size, accessor.componentType);
    }
    if (accessor.sparse.isSparse) apply_sparse(accessor, index, role, components, values);
    return values;
  }

  template <typename T>
  void apply_sparse(const tinygltf::Accessor& accessor, int index, const std::string& role, std::size_t components,
                    std::vector<T>& values) const {
    const auto& sparse = accessor.sparse;
    const std::size_t n = std::size_t(std::max(sparse.count, 0));
    const int index_type = sparse.indices.componentType;
    const std::size_t index_size = component_size(index_type);
    if (index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(index, role,
           "has sparse indices of " + component_name(index_type) +
               "; they must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    const std::size_t value_size = components * component_size(accessor.componentType);
    const unsigned char* where = view_bytes(sparse.indices.bufferView, std::size_t(sparse.indices.byteOffset),
                                            index_size, n, index_size, index, role + ", sparse indices");
    const unsigned char* what = view_bytes(sparse.values.bufferView, std::size_t(sparse.values.byteOffset),
                                           value_size, n, value_size, index, role + ", sparse values");
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t target = component<std::uint32_t>(where + i * index_size, index_type);
      if (target >= accessor.count)
        fail(index, role, "has sparse index " + std::to_string(target) + " past its " +
                              std::to_string(accessor.count) + " elements");
      for (std::size_t c = 0; c < components; ++c)
        values[target * components + c] =
            component<T>(what + i * value_size + c * component_size(accessor.componentType), accessor.componentType);
    }
  }

  const tinygltf::Model& model_;
  std::string path_;
};

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
  SceneAssembler(const tinygltf::Model& model, std::string path, const std::string& parser_warnings)
      : model_(model), path_(std::move(path)), accessors_(model, path_) {
    if (!parser_warnings.empty()) warnings_.push_back(path_ + ": " + parser_warnings);
  }

  std::shared_ptr<Scene> assemble() {
    const int scene_index = pick_scene();
    for (int root : model_.scenes[std::size_t(scene_index)].nodes) visit(root, glm::dmat4(1.0), "scene");
    if (mesh_.triangles.empty())
      throw LoadError(path_ + ": the default scene has no triangles");
    return std::make_shared<Scene>(std::move(mesh_), path_, camera_, std::move(warnings_));
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

  void visit(int index, const glm::dmat4& parent, const std::string& from) {
    if (index < 0 || std::size_t(index) >= model_.nodes.size())
      throw LoadError(path_ + ": " + from + " refers to node " + std::to_string(index) + ", which does not exist");
    if (!on_path_.insert(index).second)
      throw LoadError(path_ + ": node " + std::to_string(index) + " is its own ancestor (the node graph has a cycle)");
    const tinygltf::Node& node = model_.nodes[std::size_t(index)];
    const glm::dmat4 world = parent * local_transform(node);
    const std::string name = "node " + std::to_string(index);
    if (node.mesh >= 0) add_mesh(node.mesh, world, name);
    if (node.camera >= 0 && !camera_) take_camera(node.camera, world, name);
    for (int child : node.children) visit(child, world, name);
    on_path_.erase(index);
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
    try {
      camera.validate();
      camera_ = camera;
    } catch (const std::invalid_argument& e) {
      warnings_.push_back(path_ + ": camera " + std::to_string(index) + " ignored (" + e.what() + ")");
    }
  }

  void add_mesh(int index, const glm::dmat4& world, const std::string& node) {
    if (std::size_t(index) >= model_.meshes.size())
      throw LoadError(path_ + ": " + node + " refers to mesh " + std::to_string(index) + ", which does not exist");
    const tinygltf::Mesh& mesh = model_.meshes[std::size_t(index)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
      add_primitive(mesh.primitives[p], world, "mesh " + std::to_string(index) + " primitive " + std::to_string(p));
  }

  void add_primitive(const tinygltf::Primitive& primitive, const glm::dmat4& world, const std::string& what) {
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES) {
      warnings_.push_back(path_ + ": " + what + " skipped: mode " + std::to_string(mode) + " is not TRIANGLES");
      return;
    }
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) {
      warnings_.push_back(path_ + ": " + what + " skipped: it has no POSITION attribute");
      return;
    }
    const std::vector<float> positions = accessors_.floats(position->second, TINYGLTF_TYPE_VEC3, what + " POSITION");
    const std::size_t vertex_count = positions.size() / 3;
    std::vector<std::uint32_t> indices;
    if (primitive.indices >= 0) {
      indices = accessors_.indices(primitive.indices, what + " indices");
    } else {
      indices.resize(vertex_count);
      for (std::size_t i = 0; i < vertex_count; ++i) indices[i] = std::uint32_t(i);
    }
    if (indices.size() % 3 != 0)
      throw LoadError(path_ + ": " + what + " has " + std::to_string(indices.size()) +
                      " indices, not a multiple of 3");
    for (std::uint32_t i : indices)
      if (i >= vertex_count)
        throw LoadError(path_ + ": " + what + " uses vertex " + std::to_string(i) + ", but POSITION has only " +
                        std::to_string(vertex_count));

    const auto base = std::uint32_t(mesh_.positions.size());
    for (std::size_t v = 0; v < vertex_count; ++v) {
      const glm::vec3 p(world * glm::dvec4(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2], 1.0));
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw LoadError(path_ + ": " + what + " vertex " + std::to_string(v) +
                        " is not finite in world space (its POSITION or a node transform is not finite or too large)");
      mesh_.positions.push_back(p);
    }
    for (std::size_t t = 0; t < indices.size(); t += 3)
      mesh_.triangles.push_back({base + indices[t], base + indices[t + 1], base + indices[t + 2]});
    add_normals(primitive, world, what, vertex_count);
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
    const std::vector<float> normals = accessors_.floats(normal->second, TINYGLTF_TYPE_VEC3, what + " NORMAL");
    if (normals.size() / 3 != vertex_count)
      throw LoadError(path_ + ": " + what + " has " + std::to_string(normals.size() / 3) + " normals for " +
                      std::to_string(vertex_count) + " positions");
    mesh_.normals.resize(mesh_.positions.size() - vertex_count, glm::vec3(0.0f));
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
    for (std::size_t v = 0; v < vertex_count; ++v) {
      const glm::dvec3 n = normal_matrix * glm::dvec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
      const double length = glm::length(n);
      mesh_.normals.push_back(length > 0.0 && std::isfinite(length) ? glm::vec3(n / length) : glm::vec3(0.0f));
    }
  }

  const tinygltf::Model& model_;
  std::string path_;
  AccessorReader accessors_;
  TriangleMesh mesh_;
  std::optional<Camera> camera_;
  std::vector<std::string> warnings_;
  std::set<int> on_path_;
};

bool has_glb_magic(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  char magic[4] = {};
  file.read(magic, 4);
  return file.gcount() == 4 && std::string(magic, 4) == "glTF";
}

}  // namespace

std::shared_ptr<Scene> load_gltf(const std::string& path) {
  if (!std::ifstream(path, std::ios::binary)) throw LoadError(path + ": cannot open file");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  tinygltf::Model model;
  std::string error, warning;
  const bool ok = has_glb_magic(path) ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                                      : loader.LoadASCIIFromFile(&model, &error, &warning, path);
  if (!ok) throw LoadError(path + ": not a readable glTF 2.0 file: " + (error.empty() ? "unknown error" : error));
  return SceneAssembler(model, path, warning).assemble();
}

}  // namespace mbao
