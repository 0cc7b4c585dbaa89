// glTF's sampler wrap modes, for texture coordinates outside [0, 1]: one
// definition for alpha masks (SPEC 3.2) and bakes (SPEC 6.3).
#pragma once

#include <cstdint>
#include <string>

#include "mbao/alpha_mask.h"

namespace mbao {

// The values are the kernels' MBAO_WRAP_* (mbao/alpha_mask.h).
enum class WrapMode : std::uint32_t {
  Repeat = MBAO_WRAP_REPEAT,
  ClampToEdge = MBAO_WRAP_CLAMP_TO_EDGE,
  MirroredRepeat = MBAO_WRAP_MIRRORED_REPEAT,
};

// A glTF sampler's wrapS or wrapT (10497, 33071, 33648; anything else is REPEAT, glTF's default).
WrapMode wrap_mode_of_gltf(int gltf_wrap);
// "repeat", "mirrored-repeat" or "clamp-to-edge"; throws std::invalid_argument otherwise.
WrapMode parse_wrap_mode(const std::string& name);
std::string to_string(WrapMode mode);

}  // namespace mbao
