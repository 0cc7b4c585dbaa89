#pragma once

#include <memory>

#include "scene/scene.h"

namespace mbao {

// The measured Cornell box of SPEC 3.4 with its own camera: the same triangles,
// in the same order, as shared/scenes/cornell_box/scene.glb.
std::shared_ptr<Scene> cornell_box();

}  // namespace mbao
