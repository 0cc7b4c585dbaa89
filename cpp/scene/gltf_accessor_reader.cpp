#include "scene/gltf_accessor_reader.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "core/error.h"
#include "scene/gltf_meshopt.h"

namespace mbao {
namespace {

std::size_t component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

std::string component_name(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    default: return "component type " + std::to_string(component_type);
  }
}

// One component, of an integer type or FLOAT, converted to T.
template <typename T>
T component(const unsigned char* p, int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return T(static_cast<std::int8_t>(*p));
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return T(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return T(*p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return T(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return T(v);
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return T(v);
    }
  }
}

// Normalized integers as glTF 2.0 3.11 decodes them: signed ones to
// max(c / (2^(n-1) - 1), -1), unsigned ones to c / (2^n - 1).
void normalize(std::vector<float>& values, int component_type) {
  const float largest = component_type == TINYGLTF_COMPONENT_TYPE_BYTE            ? 127.0f
                        : component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 255.0f
                        : component_type == TINYGLTF_COMPONENT_TYPE_SHORT         ? 32767.0f
                                                                                  : 65535.0f;
  for (float& v : values) v = std::max(v / largest, -1.0f);
}

bool is_unsigned_integer(int component_type) {
  return component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

}  // namespace

std::vector<float> AccessorReader::floats(int index, int type, const std::string& role) const {
  const tinygltf::Accessor& accessor = get(index, role);
  expect_type(accessor, index, type, role);
  if (const auto found = substituted_.find(index); found != substituted_.end()) return found->second;
  if (accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
    fail(index, role, "has " + component_name(accessor.componentType) + " components; only FLOAT is supported");
  return read<float>(accessor, index, role);
}

AccessorReader::AccessorReader(const tinygltf::Model& model, std::string path)
    : model_(model),
      path_(std::move(path)),
      quantization_(std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(), "KHR_mesh_quantization") !=
                    model.extensionsUsed.end()) {}

std::vector<float> AccessorReader::quantized(int index, int type, const std::string& role) const {
  const tinygltf::Accessor& accessor = get(index, role);
  const int component_type = accessor.componentType;
  const bool small_integer =
      component_type == TINYGLTF_COMPONENT_TYPE_BYTE || component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
      component_type == TINYGLTF_COMPONENT_TYPE_SHORT || component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  if (!quantization_ || !small_integer || substituted_.count(index)) return floats(index, type, role);
  expect_type(accessor, index, type, role);
  std::vector<float> values = read<float>(accessor, index, role);
  if (accessor.normalized) normalize(values, component_type);
  return values;
}

void AccessorReader::substitute(int index, std::vector<float> values, const std::string& role) {
  const tinygltf::Accessor& accessor = get(index, role);
  const int n = components(index, role);
  if (values.size() != accessor.count * std::size_t(n))
    fail(index, role,
         "has count " + std::to_string(accessor.count) + ", but its decoded data has " +
             std::to_string(values.size() / std::size_t(n)) + " elements");
  if (accessor.normalized) normalize(values, accessor.componentType);
  substituted_[index] = std::move(values);
}

void AccessorReader::substitute_indices(int index, std::vector<std::uint32_t> values, const std::string& role) {
  const tinygltf::Accessor& accessor = get(index, role);
  if (values.size() != accessor.count)
    fail(index, role,
         "has count " + std::to_string(accessor.count) + ", but its decoded data has " + std::to_string(values.size()) +
             " indices");
  substituted_indices_[index] = std::move(values);
}

int AccessorReader::components(int index, const std::string& role) const {
  return tinygltf::GetNumComponentsInType(std::uint32_t(get(index, role).type));
}

std::vector<float> AccessorReader::texcoords(int index, const std::string& role) const {
  const tinygltf::Accessor& accessor = get(index, role);
  if (quantization_ || substituted_.count(index)) return quantized(index, TINYGLTF_TYPE_VEC2, role);
  expect_type(accessor, index, TINYGLTF_TYPE_VEC2, role);
  const int type = accessor.componentType;
  const bool normalized_integer = accessor.normalized && (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                          type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  if (type != TINYGLTF_COMPONENT_TYPE_FLOAT && !normalized_integer)
    fail(index, role,
         "has " + component_name(type) + (accessor.normalized ? " normalized" : "") +
             " components; texture coordinates must be FLOAT or normalized UNSIGNED_BYTE / UNSIGNED_SHORT");
  std::vector<float> values = read<float>(accessor, index, role);
  if (normalized_integer) {
    const float scale = type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 1.0f / 255.0f : 1.0f / 65535.0f;
    for (float& v : values) v *= scale;
  }
  return values;
}

std::vector<std::uint32_t> AccessorReader::indices(int index, const std::string& role) const {
  const tinygltf::Accessor& accessor = get(index, role);
  expect_type(accessor, index, TINYGLTF_TYPE_SCALAR, role);
  if (const auto found = substituted_indices_.find(index); found != substituted_indices_.end()) return found->second;
  if (!is_unsigned_integer(accessor.componentType))
    fail(index, role,
         "has " + component_name(accessor.componentType) +
             " components; indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  return read<std::uint32_t>(accessor, index, role);
}

std::vector<unsigned char> AccessorReader::view_bytes(int view_index, const std::string& role) const {
  const std::size_t length = buffer_view(view_index, -1, role).byteLength;
  const unsigned char* bytes = checked_bytes(view_index, 0, 1, length, 1, -1, role);
  return {bytes, bytes + length};
}

void AccessorReader::fail(int index, const std::string& role, const std::string& problem) const {
  throw LoadError(path_ + ": " + (index >= 0 ? "accessor " + std::to_string(index) + " (" + role + ")" : role) + " " +
                  problem);
}

const tinygltf::Accessor& AccessorReader::get(int index, const std::string& role) const {
  if (index < 0 || std::size_t(index) >= model_.accessors.size())
    throw LoadError(path_ + ": " + role + " refers to accessor " + std::to_string(index) + ", but the file has " +
                    std::to_string(model_.accessors.size()));
  return model_.accessors[std::size_t(index)];
}

void AccessorReader::expect_type(const tinygltf::Accessor& accessor, int index, int type,
                                 const std::string& role) const {
  if (accessor.type != type)
    fail(index, role,
         "has " + std::to_string(tinygltf::GetNumComponentsInType(std::uint32_t(accessor.type))) +
             " components per element, expected " +
             std::to_string(tinygltf::GetNumComponentsInType(std::uint32_t(type))));
}

const tinygltf::BufferView& AccessorReader::buffer_view(int view_index, int accessor_index,
                                                        const std::string& role) const {
  if (view_index < 0 || std::size_t(view_index) >= model_.bufferViews.size())
    fail(accessor_index, role, "refers to bufferView " + std::to_string(view_index) + ", which does not exist");
  return model_.bufferViews[std::size_t(view_index)];
}

// The bytes [offset, offset + stride * (count - 1) + element) of a buffer view,
// checked against the view and its buffer.
const unsigned char* AccessorReader::checked_bytes(int view_index, std::size_t offset, std::size_t stride,
                                                   std::size_t count, std::size_t element, int accessor_index,
                                                   const std::string& role) const {
  const unsigned char* view = view_data(view_index, accessor_index, role);
  const std::size_t length = model_.bufferViews[std::size_t(view_index)].byteLength;
  const std::size_t max = std::numeric_limits<std::size_t>::max();
  const bool overflows = count > 0 && (count - 1 > (max - element) / std::max<std::size_t>(stride, 1));
  const std::size_t span = count == 0 ? 0 : (count - 1) * stride + element;
  if (overflows || offset > length || span > length - offset)
    fail(accessor_index, role,
         "declares " + std::to_string(count) + " elements, more than bufferView " + std::to_string(view_index) +
             " holds");
  return view + offset;
}

// The byteLength bytes a buffer view holds: its buffer's, checked, or, for a
// meshopt-compressed view, their decoding (kept for the view's next reader).
const unsigned char* AccessorReader::view_data(int view_index, int accessor_index, const std::string& role) const {
  const tinygltf::BufferView& view = buffer_view(view_index, accessor_index, role);
  if (const auto kept = decoded_views_.find(view_index); kept != decoded_views_.end()) return kept->second.data();
  if (std::optional<std::vector<unsigned char>> decoded = decoded_meshopt_view(model_, view_index, path_)) {
    if (decoded->size() < view.byteLength)
      fail(accessor_index, role,
           "uses bufferView " + std::to_string(view_index) + ", whose byteLength " + std::to_string(view.byteLength) +
               " is more than its meshopt encoding decodes to (" + std::to_string(decoded->size()) + " bytes)");
    return decoded_views_.emplace(view_index, std::move(*decoded)).first->second.data();
  }
  if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
    fail(accessor_index, role,
         "uses bufferView " + std::to_string(view_index) + " of missing buffer " + std::to_string(view.buffer));
  const std::vector<unsigned char>& buffer = model_.buffers[std::size_t(view.buffer)].data;
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
    fail(accessor_index, role,
         "uses bufferView " + std::to_string(view_index) + ", which runs past the end of buffer " +
             std::to_string(view.buffer));
  return buffer.data() + view.byteOffset;
}

// Without a bufferView an accessor is zeros (sparse values may replace some),
// so nothing in the file bounds its count; it is held to the bytes the file's
// buffers have, so that a huge declared count is refused, not allocated.
void AccessorReader::check_zeros_count(const tinygltf::Accessor& accessor, int index, const std::string& role) const {
  std::size_t buffer_bytes = 0;
  for (const tinygltf::Buffer& buffer : model_.buffers) buffer_bytes += buffer.data.size();
  if (accessor.count > buffer_bytes)
    fail(index, role,
         "has no bufferView and declares " + std::to_string(accessor.count) + " elements, more than the " +
             std::to_string(buffer_bytes) + " bytes of the file's buffers");
}

template <typename T>
std::vector<T> AccessorReader::read(const tinygltf::Accessor& accessor, int index, const std::string& role) const {
  const std::size_t components = std::size_t(tinygltf::GetNumComponentsInType(std::uint32_t(accessor.type)));
  const std::size_t size = component_size(accessor.componentType);
  const std::size_t element = components * size;
  const unsigned char* bytes = nullptr;
  std::size_t stride = element;
  if (accessor.bufferView >= 0) {
    const std::size_t byte_stride = buffer_view(accessor.bufferView, index, role).byteStride;
    if (byte_stride != 0 && byte_stride < element)
      fail(index, role,
           "has " + std::to_string(element) + "-byte elements, but bufferView " + std::to_string(accessor.bufferView) +
               " has a byteStride of " + std::to_string(byte_stride));
    stride = byte_stride ? byte_stride : element;
    bytes = checked_bytes(accessor.bufferView, accessor.byteOffset, stride, accessor.count, element, index, role);
  } else {
    check_zeros_count(accessor, index, role);
  }
  std::vector<T> values(accessor.count * components, T(0));
  if (bytes)
    for (std::size_t i = 0; i < accessor.count; ++i)
      for (std::size_t c = 0; c < components; ++c)
        values[i * components + c] = component<T>(bytes + i * stride + c * size, accessor.componentType);
  if (accessor.sparse.isSparse) apply_sparse(accessor, index, role, components, values);
  return values;
}

template <typename T>
void AccessorReader::apply_sparse(const tinygltf::Accessor& accessor, int index, const std::string& role,
                                  std::size_t components, std::vector<T>& values) const {
  const auto& sparse = accessor.sparse;
  if (sparse.count < 0) fail(index, role, "has a negative sparse count, " + std::to_string(sparse.count));
  const auto n = std::size_t(sparse.count);
  const int index_type = sparse.indices.componentType;
  if (!is_unsigned_integer(index_type))
    fail(index, role,
         "has sparse indices of " + component_name(index_type) +
             "; they must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  const std::size_t index_size = component_size(index_type);
  const std::size_t value_size = components * component_size(accessor.componentType);
  const unsigned char* where = checked_bytes(sparse.indices.bufferView, std::size_t(sparse.indices.byteOffset),
                                             index_size, n, index_size, index, role + ", sparse indices");
  const unsigned char* what = checked_bytes(sparse.values.bufferView, std::size_t(sparse.values.byteOffset), value_size,
                                            n, value_size, index, role + ", sparse values");
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t target = component<std::uint32_t>(where + i * index_size, index_type);
    if (target >= accessor.count)
      fail(index, role,
           "has sparse index " + std::to_string(target) + " past its " + std::to_string(accessor.count) + " elements");
    for (std::size_t c = 0; c < components; ++c)
      values[target * components + c] =
          component<T>(what + i * value_size + c * component_size(accessor.componentType), accessor.componentType);
  }
}

}  // namespace mbao
