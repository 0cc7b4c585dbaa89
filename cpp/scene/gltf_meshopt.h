// EXT_meshopt_compression (SPEC 3.2): buffer views whose bytes are meshoptimizer's
// encoding of vertex attributes or indices in another buffer, decoded with
// meshoptimizer (Debian's libmeshoptimizer-dev).
#pragma once

#include <tiny_gltf.h>

#include <optional>
#include <string>
#include <vector>

namespace mbao {

// The bytes that bufferView `view_index` stands for, decoded, where it is
// meshopt-compressed; none where it is not. Throws LoadError naming `path`
// and the view for an encoding that does not decode or does not fit.
std::optional<std::vector<unsigned char>> decoded_meshopt_view(const tinygltf::Model& model, int view_index,
                                                               const std::string& path);

}  // namespace mbao
