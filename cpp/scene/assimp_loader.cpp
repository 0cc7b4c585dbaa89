#include "scene/assimp_loader.h"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cctype>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/assimp_scene.h"
#include "scene/gltf_container.h"
#include "scene/gltf_files.h"
#include "scene/isolated_import.h"

namespace mbao {
namespace {

// Polygons become triangles; points and lines are sorted into meshes of their
// own; UVs have v down the image, as glTF's and the mask kernels' do.
constexpr unsigned kImportSteps = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_JoinIdenticalVertices |
                                  aiProcess_ValidateDataStructure | aiProcess_FlipUVs;

// The importer's time for a file of `bytes`: options.import_seconds, else a
// minute and 10 s per MiB, far more than Assimp takes on any file that ends.
double time_limit(const LoadOptions& options, std::uintmax_t bytes) {
  return options.import_seconds > 0.0 ? options.import_seconds : 60.0 + 10.0 * double(bytes) / double(1 << 20);
}

// Why Assimp read nothing from `path`, said in terms of the file where Assimp's
// own words name its data structures.
std::string import_failure(const std::string& path, const std::string& assimp_error) {
  if (assimp_error.find("mNumMeshes is 0") != std::string::npos)
    return path + ": no meshes in it (Assimp found no geometry it could read)";
  if (assimp_error.find("contains no faces") != std::string::npos)
    return path + ": a mesh in it has vertices but no faces";
  return path + ": " + assimp_error;
}

// What `importer` read (`scene`: null where it failed), `path` naming it.
ImportedScene imported(const Assimp::Importer& importer, const aiScene* scene, const std::string& path,
                       const LoadOptions& options) {
  if (!scene) throw LoadError(import_failure(path, importer.GetErrorString()));
  return scene_from_assimp(*scene, path, options);
}

// An importer that builds no stand-in meshes: without them, a file of cameras,
// lights or bones alone has no meshes, and says so.
struct Importer : Assimp::Importer {
  Importer() { SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true); }
};

std::shared_ptr<Scene> scene_of(ImportedScene s, const std::string& path) {
  try {
    return std::make_shared<Scene>(std::move(s.mesh), path, s.camera, std::move(s.warnings), std::move(s.masks),
                                   std::move(s.uv_sets));
  } catch (const std::invalid_argument& e) {  // a mesh that cannot render, named by the path
    throw LoadError(e.what());
  }
}

}  // namespace

bool assimp_reads(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  return !extension.empty() && Assimp::Importer().IsExtensionSupported(extension);
}

// Assimp runs in a process of its own (import_isolated): Debian's build aborts
// on some malformed files.
std::shared_ptr<Scene> load_with_assimp(const std::string& path, const LoadOptions& options) {
  const auto import = [&] {
    Importer importer;
    return imported(importer, importer.ReadFile(path, kImportSteps), path, options);
  };
  std::error_code unknown;
  const std::uintmax_t bytes = std::filesystem::file_size(path, unknown);
  return scene_of(import_isolated(import, path, time_limit(options, unknown ? 0 : bytes)), path);
}

std::shared_ptr<Scene> load_with_assimp_from_memory(const unsigned char* bytes, std::size_t size,
                                                    const std::string& name, const std::string& extension,
                                                    const LoadOptions& options) {
  const auto import = [&] {
    Importer importer;
    return imported(importer, importer.ReadFileFromMemory(bytes, size, kImportSteps, extension.c_str()), name, options);
  };
  return scene_of(import_isolated(import, name, time_limit(options, size)), name);
}

namespace {

// glTF 1.0 (SPEC 3.2), which Assimp's importer reads; its failures say what the file was taken for.
std::shared_ptr<Scene> load_gltf_1(const std::string& path, const LoadOptions& options) {
  try {
    return load_with_assimp(path, options);
  } catch (const LoadError& e) {
    throw LoadError(std::string(e.what()) + " (read as glTF 1.0, a GLB of version 1 or asset.version 1.x, " +
                    "through Assimp)");
  }
}

// A file whose extension names no format and which is not glTF, as Assimp
// reads it: by its content, as its importers recognise their formats' signatures.
std::shared_ptr<Scene> load_by_content(const std::string& path, const LoadOptions& options,
                                       const std::string& gltf_error) {
  try {
    return load_with_assimp(path, options);
  } catch (const LoadError& e) {
    throw LoadError(gltf_error + "; nor did Assimp recognise its content: " + e.what());
  }
}

}  // namespace

std::shared_ptr<Scene> load_scene(const std::string& path, const LoadOptions& options) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (extension != ".gltf" && extension != ".glb" && assimp_reads(path)) return load_with_assimp(path, options);
  const std::vector<unsigned char> bytes = read_regular_file(path, "");
  try {
    return load_gltf_from_memory(bytes.data(), bytes.size(), path, std::filesystem::path(path).parent_path().string(),
                                 options);
  } catch (const LoadError& e) {
    // Asked only of a file the glTF 2.0 loader refused: a 2.0 file's JSON is not parsed twice.
    if (is_gltf_1(bytes.data(), bytes.size())) return load_gltf_1(path, options);
    if (extension == ".gltf" || extension == ".glb" || looks_like_gltf(bytes.data(), bytes.size())) throw;
    return load_by_content(path, options, e.what());
  }
}

}  // namespace mbao
