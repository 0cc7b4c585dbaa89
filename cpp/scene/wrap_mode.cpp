#include "scene/wrap_mode.h"

#include <tiny_gltf.h>

#include <stdexcept>

namespace mbao {

WrapMode wrap_mode_of_gltf(int gltf_wrap) {
  if (gltf_wrap == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return WrapMode::ClampToEdge;
  if (gltf_wrap == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return WrapMode::MirroredRepeat;
  return WrapMode::Repeat;
}

WrapMode parse_wrap_mode(const std::string& name) {
  if (name == "repeat") return WrapMode::Repeat;
  if (name == "mirrored-repeat") return WrapMode::MirroredRepeat;
  if (name == "clamp-to-edge") return WrapMode::ClampToEdge;
  throw std::invalid_argument("wrap mode must be \"repeat\", \"mirrored-repeat\" or \"clamp-to-edge\", got \"" + name +
                              "\"");
}

std::string to_string(WrapMode mode) {
  switch (mode) {
    case WrapMode::Repeat: return "repeat";
    case WrapMode::MirroredRepeat: return "mirrored-repeat";
    case WrapMode::ClampToEdge: return "clamp-to-edge";
  }
  return "?";
}

}  // namespace mbao
