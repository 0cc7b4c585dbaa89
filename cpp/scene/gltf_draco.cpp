#include "scene/gltf_draco.h"

#include <draco/compression/decode.h>

#include <memory>
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
  if (!decoded.ok())
    throw LoadError(what + ": its Draco mesh does not decode (" + decoded.status().error_msg_string() + ")");
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

}  // namespace

bool is_draco_compressed(const tinygltf::Primitive& primitive) { return primitive.extensions.count(kExtension) != 0; }

void decode_draco_primitive(const tinygltf::Primitive& primitive, AccessorReader& accessors, const std::string& what) {
  const tinygltf::Value& extension = primitive.extensions.at(kExtension);
  const std::string where = what + " " + kExtension;
  if (!extension.Get("bufferView").IsInt() || !extension.Get("attributes").IsObject())
    throw LoadError(accessors.path() + ": " + where + " lacks its bufferView or attributes");
  const std::unique_ptr<draco::Mesh> mesh = decoded_mesh(
      accessors.view_bytes(extension.Get("bufferView").GetNumberAsInt(), where), accessors.path() + ": " + where);
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
