#include "scene/assimp_loader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"

namespace mbao {
namespace {

glm::mat4 to_glm(const aiMatrix4x4& m) {
  // aiMatrix4x4 is row-major (a1..a4 the first row); glm's constructor takes columns.
  return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4, m.b4, m.c4, m.d4);
}

glm::vec3 to_glm(const aiVector3D& v) { return {v.x, v.y, v.z}; }

// What the node tree puts into the scene: triangles in world space.
class Gatherer {
 public:
  Gatherer(const aiScene& scene, bool normals) : scene_(scene), normals_(normals) {}

  void node(const aiNode& n, const glm::mat4& parent) {
    const glm::mat4 world = parent * to_glm(n.mTransformation);
    for (unsigned i = 0; i < n.mNumMeshes; ++i) mesh(*scene_.mMeshes[n.mMeshes[i]], world);
    for (unsigned i = 0; i < n.mNumChildren; ++i) node(*n.mChildren[i], world);
  }

  TriangleMesh take() {
    if (!any_normals_) mesh_.normals.clear();
    return std::move(mesh_);
  }

 private:
  void mesh(const aiMesh& m, const glm::mat4& world) {
    if (!(m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) return;  // points and lines, sorted apart
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
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices == 3)
        mesh_.triangles.push_back(glm::uvec3(face.mIndices[0], face.mIndices[1], face.mIndices[2]) + base);
    }
  }

  const aiScene& scene_;
  bool normals_, any_normals_ = false;
  TriangleMesh mesh_;
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
      warnings.push_back(name + " skipped: Assimp gives no aspect ratio for it, so its vertical field of view is "
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

}  // namespace

bool assimp_reads(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  return !extension.empty() && Assimp::Importer().IsExtensionSupported(extension);
}

std::shared_ptr<Scene> load_with_assimp(const std::string& path, const LoadOptions& options) {
  Assimp::Importer importer;
  // Polygons become triangles; points and lines are sorted into meshes of their own.
  const unsigned steps = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_JoinIdenticalVertices |
                         aiProcess_ValidateDataStructure;
  const aiScene* scene = importer.ReadFile(path, steps);
  if (!scene) throw LoadError(path + ": " + importer.GetErrorString());
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
    throw LoadError(path + ": Assimp read no complete scene from it");
  Gatherer gatherer(*scene, options.normals);
  gatherer.node(*scene->mRootNode, glm::mat4(1.0f));
  std::vector<std::string> warnings;
  if (const std::size_t dropped = dropped_primitives(*scene))
    warnings.push_back(path + ": " + std::to_string(dropped) + " points and lines skipped; only triangles render");
  std::optional<Camera> camera = first_camera(*scene, path, warnings);
  TriangleMesh mesh = gatherer.take();
  if (mesh.triangles.empty()) throw LoadError(path + ": no triangles in it");
  try {
    return std::make_shared<Scene>(std::move(mesh), path, camera, std::move(warnings));
  } catch (const std::invalid_argument& e) {  // a mesh that cannot render, named by the path
    throw LoadError(e.what());
  }
}

std::shared_ptr<Scene> load_scene(const std::string& path, const LoadOptions& options) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (extension != ".gltf" && extension != ".glb" && assimp_reads(path)) return load_with_assimp(path, options);
  return load_gltf(path, options);
}

}  // namespace mbao
