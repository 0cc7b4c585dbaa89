#include "scene/gltf_files.h"

#include <fstream>
#include <system_error>

#include "core/error.h"

namespace mbao {
namespace {

// Why `file` cannot be read as a whole, or "" when it can be.
std::string unreadable(const std::filesystem::path& file) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  if (!std::filesystem::exists(status)) return "no such file";
  if (!std::filesystem::is_regular_file(status)) return "not a regular file";
  return "";
}

// tinygltf's own FileExists opens the file, which blocks on a FIFO.
bool file_exists(const std::string& file, void*) {
  std::error_code error;
  return std::filesystem::exists(file, error);
}

bool read_whole_file(std::vector<unsigned char>* bytes, std::string* error, const std::string& file, void*) {
  try {
    *bytes = read_regular_file(file, "");
    return true;
  } catch (const LoadError& e) {
    *error += e.what();
    return false;
  }
}

}  // namespace

std::vector<unsigned char> read_regular_file(const std::filesystem::path& file, const std::string& what) {
  const std::string prefix = (what.empty() ? "" : what + ": ") + "cannot read " + file.string() + ": ";
  if (const std::string problem = unreadable(file); !problem.empty()) throw LoadError(prefix + problem);
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw LoadError(prefix + "it cannot be opened");
  const std::streamoff size = in.tellg();
  if (size < 0) throw LoadError(prefix + "its size cannot be read");
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  if (in.gcount() != std::streamsize(bytes.size()) || in.peek() != std::ifstream::traits_type::eof())
    throw LoadError(prefix + "it changed while being read");
  return bytes;
}

tinygltf::FsCallbacks regular_file_callbacks() {
  return {file_exists, tinygltf::ExpandFilePath, read_whole_file, tinygltf::WriteWholeFile, nullptr};
}

}  // namespace mbao
