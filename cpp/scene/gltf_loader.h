#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "scene/scene.h"

namespace mbao {

struct LoadOptions {
  bool normals = true;     // read vertex normals (what normals="shading" uses)
  bool texcoords = false;  // read every UV set, the triangles' materials and their occlusion textures (Scene::uv_sets)
  // With texcoords, an Assimp format's materials' base colours too (MaterialUvs::base_color): what bake_file
  // writes them as. A glTF file's materials stay in the file.
  bool base_colors = false;
  // Assimp's formats: how long the importer may take, in seconds; 0: 60 s and 10 s more per MiB of the file.
  double import_seconds = 0.0;
};

// Loads a glTF 2.0 file (.gltf or .glb) per SPEC 3.2: every triangle mesh of
// the default scene in world space, vertex normals where present, the alpha
// masks of MASK materials and the first perspective camera. Nothing else is
// read: no other attribute, and no image but the alpha of mask textures.
// Throws LoadError naming the file and the element.
std::shared_ptr<Scene> load_gltf(const std::string& path, const LoadOptions& options = {});

// The same from a file's bytes already in memory (.gltf JSON or .glb, told
// apart by the GLB magic): `name` stands for the file in messages and names
// the scene; external buffers and images are looked up in `base_dir`.
std::shared_ptr<Scene> load_gltf_from_memory(const unsigned char* bytes, std::size_t size, const std::string& name,
                                             const std::string& base_dir, const LoadOptions& options = {});

}  // namespace mbao
