#pragma once

#include <memory>
#include <string>

#include "scene/gltf_loader.h"
#include "scene/scene.h"

namespace mbao {

// Whether Assimp reads files with this path's extension (.obj, .ply, .stl,
// .fbx, .dae, .3ds, ...), case aside.
bool assimp_reads(const std::string& path);

// Loads a file through Assimp (SPEC 3.2), in a process of its own, read as
// scene_from_assimp says (scene/assimp_scene.h). Throws LoadError naming the
// file and what Assimp found wrong.
std::shared_ptr<Scene> load_with_assimp(const std::string& path, const LoadOptions& options = {});

// The same from a file's bytes in memory, read as `extension` ("obj", "ply",
// ...) says; `name` stands for the file in messages and names the scene.
// Files it refers to (an OBJ's materials, images) are looked up from the
// working directory.
std::shared_ptr<Scene> load_with_assimp_from_memory(const unsigned char* bytes, std::size_t size,
                                                    const std::string& name, const std::string& extension,
                                                    const LoadOptions& options = {});

// mbao.load's reader: glTF (.gltf, .glb, and files whose extension Assimp
// does not know, which the glTF loader tells apart by their content) through
// tinygltf, every other format Assimp reads through Assimp; a file of an
// unknown extension that is not glTF, through Assimp by its content.
std::shared_ptr<Scene> load_scene(const std::string& path, const LoadOptions& options = {});

}  // namespace mbao
