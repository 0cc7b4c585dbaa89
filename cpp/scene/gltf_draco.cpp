#include "scene/gltf_draco.h"

#include <draco/compression/decode.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/error.h"

namespace mbao {
namespace {

constexpr const char* kExtension = "KHR_draco_mesh_compression";

std::unique_ptr<draco::Mesh> decoded_mesh(const std::vector<unsigned char>& bytes, const std::string& what) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) throw LoadError(what + ": its Draco mesh does not decode (" + decoded.status().error_msg_string() + ")");
  return std::move(decoded).value();
}

// The attribute's values at the mesh's points, `components` a point.
std::vector<float> point_values(const draco::Mesh& mesh, const draco::PointAttribute& attribute, int components) {
  std::vector<float> values(std::size_t(mesh.num_points()) * std::size_t(components));
  for (draco::PointIndex point(0); point < mesh.num_points(); ++point)
    attribute.ConvertValue<float>(attribute.mapped_index(point), std::int8_t(components),
                                  &values[std::size_t(point.value()) * std::size_t(components)]);
  return values;
}

std::vector<std::uint32_t> face_indices(const draco::Mesh& mesh) {
  std::vector<std::uint32_t> indices;
  indices.reserve(3 * std::size_t(mesh.num_faces()));
  for (draco::FaceIndex face(0); face < mesh.num_faces(); ++face)
    for (int corner = 0; corner < 3; ++corner) indices.push_back(mesh.face(face)[corner].value());
  return indices;
}

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
          !primitive["extensions"].contains(kExtension))
        continue;
      const nlohmann::json& extension = primitive["extensions"][kExtension];
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

}  // namespace

std::vector<unsigned char> with_draco_indices_placed(const unsigned char* bytes, std::size_t size, bool glb) {
  const std::size_t json_size = glb ? read_u32(bytes + 12) : size;
  const unsigned char* json_bytes = glb ? bytes + 20 : bytes;
  const std::string_view text(reinterpret_cast<const char*>(json_bytes), json_size);
  if (text.find(kExtension) == std::string_view::npos) return {};
  nlohmann::json document = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded() || !document.is_object() || !place_draco_indices(document)) return {};
  const std::string json = document.dump();
  if (glb) return glb_with_json(bytes, size, json);
  return std::vector<unsigned char>(json.begin(), json.end());
}

bool is_draco_compressed(const tinygltf::Primitive& primitive) {
  return primitive.extensions.count(kExtension) != 0;
}

void decode_draco_primitive(const tinygltf::Primitive& primitive, AccessorReader& accessors, const std::string& what) {
  const tinygltf::Value& extension = primitive.extensions.at(kExtension);
  const std::string where = what + " " + kExtension;
  if (!extension.Get("bufferView").IsInt() || !extension.Get("attributes").IsObject())
    throw LoadError(accessors.path() + ": " + where + " lacks its bufferView or attributes");
  const std::unique_ptr<draco::Mesh> mesh =
      decoded_mesh(accessors.view_bytes(extension.Get("bufferView").GetNumberAsInt(), where),
                   accessors.path() + ": " + where);
  const tinygltf::Value& ids = extension.Get("attributes");
  for (const std::string& name : ids.Keys()) {
    const auto accessor = primitive.attributes.find(name);
    if (accessor == primitive.attributes.end()) continue;  // compressed but not listed: unused
    const draco::PointAttribute* attribute =
        ids.Get(name).IsInt() ? mesh->GetAttributeByUniqueId(std::uint32_t(ids.Get(name).GetNumberAsInt())) : nullptr;
    if (!attribute)
      throw LoadError(accessors.path() + ": " + where + " maps " + name + " to no attribute of its Draco mesh");
    const int components = accessors.components(accessor->second, what + " " + name);
    if (attribute->num_components() < components)
      throw LoadError(accessors.path() + ": " + where + ": " + name + " has " +
                      std::to_string(attribute->num_components()) + " components in its Draco mesh, " +
                      std::to_string(components) + " in its accessor");
    accessors.substitute(accessor->second, point_values(*mesh, *attribute, components), what + " " + name);
  }
  if (primitive.indices >= 0) accessors.substitute_indices(primitive.indices, face_indices(*mesh), what + " indices");
}

}  // namespace mbao
