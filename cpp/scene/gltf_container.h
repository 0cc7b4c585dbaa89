#pragma once

#include <cstddef>
#include <string>

namespace mbao {

enum class GltfContainer { Json, Glb };

// Deepest JSON nesting of arrays and objects accepted. tinygltf copies
// `extras` recursively, one stack frame per level, so deeper JSON would
// overflow the stack; glTF itself needs about 10 levels.
constexpr std::size_t kMaxJsonDepth = 128;

// What a glTF file's bytes hold, checked before tinygltf parses them for what
// tinygltf does not check or reports without naming the part: a GLB's header
// (version 2, declared length within the file) and chunk lengths, and the
// JSON's nesting depth. Throws LoadError naming `name` and the part.
GltfContainer check_gltf_container(const unsigned char* bytes, std::size_t size, const std::string& name);

}  // namespace mbao
