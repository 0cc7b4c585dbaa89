#include "scene/gltf_tinygltf_workarounds.h"

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace mbao {
namespace {

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kMeshopt = "EXT_meshopt_compression";

// Points each Draco primitive's index accessor that has no bufferView at the primitive's compressed one.
bool place_draco_indices(nlohmann::json& document) {
  if (!document.contains("meshes") || !document["meshes"].is_array() || !document.contains("accessors") ||
      !document["accessors"].is_array())
    return false;
  bool changed = false;
  for (auto& mesh : document["meshes"]) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (auto& primitive : mesh["primitives"]) {
      if (!primitive.is_object() || !primitive.contains("indices") || !primitive["indices"].is_number_unsigned() ||
          !primitive.contains("extensions") || !primitive["extensions"].is_object() ||
          !primitive["extensions"].contains(kDraco))
        continue;
      const nlohmann::json& extension = primitive["extensions"][kDraco];
      const auto accessor = primitive["indices"].get<std::size_t>();
      if (!extension.is_object() || !extension.contains("bufferView") || accessor >= document["accessors"].size() ||
          !document["accessors"][accessor].is_object() || document["accessors"][accessor].contains("bufferView"))
        continue;  // left as it is, for the loader to name what is wrong
      document["accessors"][accessor]["bufferView"] = extension["bufferView"];
      changed = true;
    }
  }
  return changed;
}

std::uint32_t read_u32(const unsigned char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

void append_u32(std::vector<unsigned char>& out, std::uint32_t v) {
  const auto* p = reinterpret_cast<const unsigned char*>(&v);
  out.insert(out.end(), p, p + 4);
}

// A GLB with its JSON chunk replaced by `json`, space-padded as GLB requires (check_gltf_container has checked
// the header and chunk lengths).
std::vector<unsigned char> glb_with_json(const unsigned char* bytes, std::size_t size, std::string json) {
  json.append((4 - json.size() % 4) % 4, ' ');
  const std::size_t old_json = read_u32(bytes + 12), rest = 20 + old_json;
  std::vector<unsigned char> out(bytes, bytes + 12);
  append_u32(out, std::uint32_t(json.size()));
  append_u32(out, read_u32(bytes + 16));
  out.insert(out.end(), json.begin(), json.end());
  out.insert(out.end(), bytes + std::min(rest, size), bytes + size);
  const auto length = std::uint32_t(out.size());
  std::memcpy(out.data() + 8, &length, 4);
  return out;
}

// Gives each meshopt fallback buffer without a uri a byteLength of 1.
bool shrink_meshopt_fallbacks(nlohmann::json& document) {
  if (!document.contains("buffers") || !document["buffers"].is_array()) return false;
  bool changed = false;
  for (auto& buffer : document["buffers"]) {
    if (!buffer.is_object() || buffer.contains("uri") || !buffer.contains("extensions") ||
        !buffer["extensions"].is_object() || !buffer["extensions"].contains(kMeshopt))
      continue;
    const nlohmann::json& extension = buffer["extensions"][kMeshopt];
    if (extension.is_object() && extension.value("fallback", false)) {
      buffer["byteLength"] = 1;
      changed = true;
    }
  }
  return changed;
}

}  // namespace

std::vector<unsigned char> tinygltf_readable(const unsigned char* bytes, std::size_t size, bool glb) {
  const std::size_t json_size = glb ? read_u32(bytes + 12) : size;
  const unsigned char* json_bytes = glb ? bytes + 20 : bytes;
  const std::string_view text(reinterpret_cast<const char*>(json_bytes), json_size);
  if (text.find(kDraco) == std::string_view::npos && text.find(kMeshopt) == std::string_view::npos) return {};
  nlohmann::json document = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded() || !document.is_object()) return {};  // tinygltf names what is wrong
  const bool placed = place_draco_indices(document);
  if (!shrink_meshopt_fallbacks(document) && !placed) return {};
  const std::string json = document.dump();
  if (glb) return glb_with_json(bytes, size, json);
  return std::vector<unsigned char>(json.begin(), json.end());
}

}  // namespace mbao
