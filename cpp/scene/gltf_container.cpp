#include "scene/gltf_container.h"

#include <cstdint>
#include <cstring>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace mbao {
namespace {

constexpr std::size_t kGlbHeader = 12;
constexpr std::size_t kChunkHeader = 8;
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;

std::uint32_t little_endian_u32(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

bool starts_like_json_object(const unsigned char* bytes, std::size_t size) {
  std::size_t i = size >= 3 && std::memcmp(bytes, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;  // a UTF-8 byte order mark
  while (i < size && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\n' || bytes[i] == '\r')) ++i;
  return i < size && bytes[i] == '{';
}

void check_json_depth(const unsigned char* text, std::size_t size, const std::string& name) {
  std::size_t depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < size; ++i) {
    const unsigned char c = text[i];
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw LoadError(name + ": the JSON nests arrays and objects more than " + std::to_string(kMaxJsonDepth) +
                        " deep (at byte " + std::to_string(i) + " of the JSON)");
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

// The GLB's JSON chunk, after checking every length the header and chunk
// headers declare against the bytes there are.
std::string_view glb_json_chunk(const unsigned char* bytes, std::size_t size, const std::string& name) {
  if (size < kGlbHeader + kChunkHeader)
    throw LoadError(name + ": GLB file of " + std::to_string(size) +
                    " bytes is too short for its header and JSON chunk (" + std::to_string(kGlbHeader + kChunkHeader) +
                    " bytes)");
  const std::uint32_t version = little_endian_u32(bytes + 4);
  if (version != 2)
    throw LoadError(name + ": GLB header has version " + std::to_string(version) + "; only version 2 is supported");
  const std::uint32_t length = little_endian_u32(bytes + 8);
  if (length > size)
    throw LoadError(name + ": GLB header declares " + std::to_string(length) + " bytes, but the file has only " +
                    std::to_string(size) + " (truncated?)");
  // Every offset below is measured within `length`, so it must cover the headers.
  if (length < kGlbHeader + kChunkHeader)
    throw LoadError(name + ": GLB header declares " + std::to_string(length) +
                    " bytes, too few for its header and JSON chunk header (" +
                    std::to_string(kGlbHeader + kChunkHeader) + " bytes)");
  const std::uint32_t json_length = little_endian_u32(bytes + kGlbHeader);
  if (little_endian_u32(bytes + kGlbHeader + 4) != kJsonChunk)
    throw LoadError(name + ": the first GLB chunk is not a JSON chunk");
  if (json_length > length - (kGlbHeader + kChunkHeader))
    throw LoadError(name + ": GLB JSON chunk declares " + std::to_string(json_length) + " bytes, past the end of the " +
                    std::to_string(length) + "-byte GLB");
  const std::size_t bin_at = kGlbHeader + kChunkHeader + json_length;
  if (length - bin_at >= kChunkHeader) {
    const std::uint32_t bin_length = little_endian_u32(bytes + bin_at);
    if (bin_length > length - bin_at - kChunkHeader)
      throw LoadError(name + ": GLB BIN chunk declares " + std::to_string(bin_length) + " bytes, past the end of the " +
                      std::to_string(length) + "-byte GLB");
  }
  return {reinterpret_cast<const char*>(bytes + kGlbHeader + kChunkHeader), json_length};
}

}  // namespace

bool looks_like_gltf(const unsigned char* bytes, std::size_t size) {
  return (size >= 4 && std::memcmp(bytes, "glTF", 4) == 0) || starts_like_json_object(bytes, size);
}

GltfContainer check_gltf_container(const unsigned char* bytes, std::size_t size, const std::string& name) {
  if (size >= 4 && std::memcmp(bytes, "glTF", 4) == 0) {
    const std::string_view json = glb_json_chunk(bytes, size, name);
    check_json_depth(reinterpret_cast<const unsigned char*>(json.data()), json.size(), name);
    return GltfContainer::Glb;
  }
  if (!starts_like_json_object(bytes, size))
    throw LoadError(name + (size == 0 ? ": the file is empty"
                                      : ": neither a GLB file (it does not start with 'glTF') nor glTF JSON (it "
                                        "does not start with '{')"));
  check_json_depth(bytes, size, name);
  return GltfContainer::Json;
}

bool is_gltf_1(const unsigned char* bytes, std::size_t size) {
  if (size >= 8 && std::memcmp(bytes, "glTF", 4) == 0) {
    std::uint32_t version;
    std::memcpy(&version, bytes + 4, sizeof version);
    return version == 1;
  }
  if (!starts_like_json_object(bytes, size)) return false;
  try {
    check_json_depth(bytes, size, "");  // nlohmann parses by recursion too
  } catch (const LoadError&) {
    return false;
  }
  const nlohmann::json doc = nlohmann::json::parse(bytes, bytes + size, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return false;
  const auto asset = doc.find("asset");
  if (asset == doc.end() || !asset->is_object()) return false;
  // Writers before 1.0 was final (collada2gltf) wrote the version as the number 1.
  const auto version = asset->find("version");
  if (version != asset->end() && version->is_number()) return version->get<double>() == 1.0;
  return version != asset->end() && version->is_string() && version->get<std::string>().rfind("1.", 0) == 0;
}

}  // namespace mbao
