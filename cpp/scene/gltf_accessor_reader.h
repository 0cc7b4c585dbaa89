#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <vector>

namespace mbao {

// Reads glTF accessors into flat arrays: bounds-checked against their buffer
// views and buffers, sparse substitution applied. Every problem is a
// LoadError naming the file, the accessor and its role.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, std::string path);

  // FLOAT elements of `type` (e.g. TINYGLTF_TYPE_VEC3), components in order.
  std::vector<float> floats(int index, int type, const std::string& role) const;
  // As floats, or, for a file that uses KHR_mesh_quantization, elements of
  // 8- or 16-bit integers, signed or not, normalized (to [-1, 1] or [0, 1],
  // as glTF decodes them) or not, as floats.
  std::vector<float> quantized(int index, int type, const std::string& role) const;
  // VEC2 texture coordinates: FLOAT, or normalized UNSIGNED_BYTE / UNSIGNED_SHORT.
  std::vector<float> texcoords(int index, const std::string& role) const;
  // SCALAR UNSIGNED_BYTE / SHORT / INT indices.
  std::vector<std::uint32_t> indices(int index, const std::string& role) const;
  // The bytes of a buffer view, checked against its buffer.
  std::vector<unsigned char> view_bytes(int view_index, const std::string& role) const;

 private:
  [[noreturn]] void fail(int index, const std::string& role, const std::string& problem) const;
  const tinygltf::Accessor& get(int index, const std::string& role) const;
  void expect_type(const tinygltf::Accessor& accessor, int index, int type, const std::string& role) const;
  const tinygltf::BufferView& buffer_view(int view_index, int accessor_index, const std::string& role) const;
  void check_zeros_count(const tinygltf::Accessor& accessor, int index, const std::string& role) const;
  const unsigned char* checked_bytes(int view_index, std::size_t offset, std::size_t stride, std::size_t count,
                                     std::size_t element, int accessor_index, const std::string& role) const;
  template <typename T>
  std::vector<T> read(const tinygltf::Accessor& accessor, int index, const std::string& role) const;
  template <typename T>
  void apply_sparse(const tinygltf::Accessor& accessor, int index, const std::string& role, std::size_t components,
                    std::vector<T>& values) const;

  const tinygltf::Model& model_;
  std::string path_;
  bool quantization_;  // the file uses KHR_mesh_quantization
};

}  // namespace mbao
