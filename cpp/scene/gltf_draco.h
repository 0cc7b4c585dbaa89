// KHR_draco_mesh_compression (SPEC 3.2): a primitive whose attributes and
// indices are a Draco-compressed mesh in a bufferView, decoded with Google's
// Draco library (Debian's libdraco-dev).
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <string>
#include <vector>

#include "scene/gltf_accessor_reader.h"

namespace mbao {

// Whether `primitive` is Draco-compressed.
bool is_draco_compressed(const tinygltf::Primitive& primitive);

// Decodes the primitive's compressed mesh and hands `accessors` the values of
// the accessors it stands for: each attribute the extension maps, and the
// indices. Throws LoadError naming `what` (the primitive) for a mesh that
// does not decode or does not match its accessors.
void decode_draco_primitive(const tinygltf::Primitive& primitive, AccessorReader& accessors, const std::string& what);

}  // namespace mbao

namespace mbao {

// tinygltf 2.8 refuses a primitive whose index accessor has no bufferView,
// which a Draco-compressed primitive's has not (its indices are in the
// compressed mesh). The file's bytes with each such accessor pointed at its
// primitive's compressed bufferView, which tinygltf accepts; the accessor's
// values are the decoded mesh's (decode_draco_primitive), never those bytes.
// Empty where the file uses no Draco compression: then it is read as it is.
std::vector<unsigned char> with_draco_indices_placed(const unsigned char* bytes, std::size_t size, bool glb);

}  // namespace mbao
