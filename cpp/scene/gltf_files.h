#pragma once

#include <tiny_gltf.h>

#include <filesystem>
#include <string>
#include <vector>

namespace mbao {

// The whole of a regular file. Anything else is refused: a directory, and a
// FIFO or device (/dev/zero, /dev/stdin), whose reads could block or never
// end. Throws LoadError "<what>: ..." naming the file.
std::vector<unsigned char> read_regular_file(const std::filesystem::path& file, const std::string& what);

// tinygltf's file callbacks, reading external buffers and images with
// read_regular_file.
tinygltf::FsCallbacks regular_file_callbacks();

}  // namespace mbao
