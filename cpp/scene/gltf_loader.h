#pragma once

#include <memory>
#include <string>

#include "scene/scene.h"

namespace mbao {

// Loads a glTF 2.0 file (.gltf or .glb) per SPEC 3.2: every triangle mesh of
// the default scene in world space, vertex normals where present, and the
// first perspective camera. Throws LoadError naming the file and the element.
std::shared_ptr<Scene> load_gltf(const std::string& path);

}  // namespace mbao
