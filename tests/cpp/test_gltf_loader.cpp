#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/gltf_loader.h"

namespace mbao {
namespace {

std::vector<unsigned char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The bytes lie in a buffer of exactly their size, so that AddressSanitizer
// sees any read past their end.
std::string load_error(const std::vector<unsigned char>& bytes, const std::string& name, const std::string& base_dir) {
  try {
    load_gltf_from_memory(bytes.data(), bytes.size(), name, base_dir);
  } catch (const LoadError& e) {
    return e.what();
  }
  return "no error";
}

std::string load_error(const std::string& text, const std::string& name, const std::string& base_dir) {
  return load_error(std::vector<unsigned char>(text.begin(), text.end()), name, base_dir);
}

// One triangle whose 36 bytes of positions are in `bin`, beside the JSON.
std::string triangle_gltf(const std::string& bin) {
  return R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"uri": ")" +
         bin + R"(", "byteLength": 36}]})";
}

TEST(GltfLoader, FromMemoryEqualsFromFile) {
  const std::string path = std::string(MBAO_TEST_DATA) + "/cornell_box.glb";
  const std::vector<unsigned char> bytes = file_bytes(path);
  const auto from_file = load_gltf(path);
  const auto from_memory = load_gltf_from_memory(bytes.data(), bytes.size(), "cornell in memory", MBAO_TEST_DATA);
  EXPECT_EQ(from_memory->name(), "cornell in memory");
  EXPECT_EQ(from_memory->mesh().positions, from_file->mesh().positions);
  EXPECT_EQ(from_memory->mesh().triangles, from_file->mesh().triangles);
}

TEST(GltfLoader, FromMemoryFindsExternalFilesInTheBaseDirectory) {
  const std::string dir = testing::TempDir();
  const float corners[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::ofstream(dir + "/memory_triangle.bin", std::ios::binary).write(reinterpret_cast<const char*>(corners), 36);
  const std::string text = triangle_gltf("memory_triangle.bin");
  const auto scene =
      load_gltf_from_memory(reinterpret_cast<const unsigned char*>(text.data()), text.size(), "triangle", dir);
  ASSERT_EQ(scene->mesh().positions.size(), 3u);
  EXPECT_EQ(scene->mesh().positions[1], glm::vec3(1, 0, 0));

  const std::string elsewhere = load_error(text, "triangle", dir + "/no_such_directory");
  EXPECT_EQ(elsewhere.rfind("triangle: ", 0), 0u) << elsewhere;
  EXPECT_NE(elsewhere.find("memory_triangle.bin"), std::string::npos) << elsewhere;
}

TEST(GltfLoader, FromMemoryMessagesNameTheGivenName) {
  EXPECT_EQ(load_error("glTF\x01\0\0\0", "bytes from somewhere", "").rfind("bytes from somewhere: ", 0), 0u);
  EXPECT_EQ(load_error("", "nothing", "").rfind("nothing: ", 0), 0u);
  EXPECT_EQ(load_error("{", "half", "").rfind("half: ", 0), 0u);
}

// A GLB of `size` bytes (at least 20) whose header declares `declared_length`:
// the 12-byte header, then a JSON chunk header of an empty chunk, then zeros.
std::vector<unsigned char> glb_declaring(std::uint32_t declared_length, std::size_t size) {
  std::vector<unsigned char> bytes(size, 0);
  const unsigned char header[20] = {'g', 'l', 'T', 'F', 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 'J', 'S', 'O', 'N'};
  std::copy(std::begin(header), std::end(header), bytes.begin());
  for (int i = 0; i < 4; ++i) bytes[8 + i] = static_cast<unsigned char>(declared_length >> (8 * i));
  return bytes;
}

// Found by the fuzzer: a declared length shorter than the headers once made
// the BIN chunk's offset wrap around and the check read past the buffer.
TEST(GltfLoader, GlbDeclaringFewerBytesThanItsHeadersIsRefused) {
  for (const std::uint32_t declared : {0u, 12u, 16u, 19u}) {
    for (const std::size_t size : {std::size_t(20), std::size_t(23), std::size_t(64)}) {
      const std::string message = load_error(glb_declaring(declared, size), "short.glb", "");
      EXPECT_NE(message.find("GLB header declares " + std::to_string(declared) + " bytes, too few"), std::string::npos)
          << "declared " << declared << " in " << size << " bytes: " << message;
    }
  }
}

}  // namespace
}  // namespace mbao
