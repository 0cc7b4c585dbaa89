// KHR_draco_mesh_compression (SPEC 3.2): a primitive whose attributes and
// indices are a Draco-compressed mesh in a bufferView, decoded with Google's
// Draco library (Debian's libdraco-dev).
#pragma once

#include <tiny_gltf.h>

#include <string>

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
