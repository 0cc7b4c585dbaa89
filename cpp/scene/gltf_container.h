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

// Whether the bytes start as a glTF file does: the GLB magic, or a JSON object.
bool looks_like_gltf(const unsigned char* bytes, std::size_t size);

// Whether the bytes are a glTF 1.0 file: a GLB of version 1 (KHR_binary_glTF),
// or JSON whose asset.version is 1.x (or the number 1, as writers before 1.0
// was final put it). mbao's glTF loader reads glTF 2.0;
// Assimp's importer reads 1.0. False for anything else, malformed too.
bool is_gltf_1(const unsigned char* bytes, std::size_t size);

}  // namespace mbao
