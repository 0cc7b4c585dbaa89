// mbao's reading of a scene Assimp has imported (SPEC 3.2), apart from the
// import itself: the loader runs Assimp in a child process and this there, and
// the aiScene fuzzer (fuzz/assimp_scene_fuzzer.cpp) runs it on scenes it builds.
#pragma once

#include <string>

#include "scene/gltf_loader.h"
#include "scene/isolated_import.h"

struct aiScene;

namespace mbao {

// Every triangle mesh of the scene's node tree in world space (the nodes'
// transforms applied), vertex normals where the file has them and
// options.normals asks, alpha masks from the materials' opacity and diffuse
// maps, the first perspective camera, and UV sets and materials where
// options.texcoords asks. `scene` is as Assimp's aiProcess_ValidateDataStructure
// leaves it: indices in range, faces of 1-3 corners sorted into meshes by
// aiProcess_SortByPType. A scene that Assimp flags incomplete loads with a
// warning where it has triangles. Points and lines are dropped, with a warning;
// an image that cannot be read warns and leaves its material opaque. Throws
// LoadError naming `path` where no triangle is left.
ImportedScene scene_from_assimp(const aiScene& scene, const std::string& path, const LoadOptions& options);

}  // namespace mbao
