// What tinygltf 2.8 (Debian's) refuses in a valid glTF file, made readable to it
// before it parses the file, each change one that no reader of mbao's relies on.
#pragma once

#include <cstddef>
#include <vector>

namespace mbao {

// The file's bytes with these changes, or empty where none is needed (then it
// is read as it is):
// - tinygltf refuses a primitive whose index accessor has no bufferView, which
//   a Draco-compressed primitive's has not (its indices are in the compressed
//   mesh): such an accessor is pointed at its primitive's compressed
//   bufferView. Its values are the decoded mesh's (decode_draco_primitive),
//   never those bytes.
// - tinygltf reads every buffer of a GLB without a uri from the binary chunk,
//   and refuses one longer than the chunk, which a meshopt fallback buffer may
//   be: such a buffer, which holds nothing a reader may read (its views are
//   decoded from another, decoded_meshopt_view), is given a byteLength of 1.
std::vector<unsigned char> tinygltf_readable(const unsigned char* bytes, std::size_t size, bool glb);

}  // namespace mbao
