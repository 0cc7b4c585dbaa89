#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <map>
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

  // Accessor `index`'s values as a decoder gave them (KHR_draco_mesh_compression),
  // read in place of its bufferView from then on: `count` elements of its
  // type's components, as floats (normalized integer types decoded as glTF
  // says), or indices. Throws LoadError where the count is not the accessor's.
  void substitute(int index, std::vector<float> values, const std::string& role);
  void substitute_indices(int index, std::vector<std::uint32_t> values, const std::string& role);
  // The components of accessor `index`'s type (3 for VEC3).
  int components(int index, const std::string& role) const;
  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(int index, const std::string& role, const std::string& problem) const;
  const tinygltf::Accessor& get(int index, const std::string& role) const;
  void expect_type(const tinygltf::Accessor& accessor, int index, int type, const std::string& role) const;
  const tinygltf::BufferView& buffer_view(int view_index, int accessor_index, const std::string& role) const;
  void check_zeros_count(const tinygltf::Accessor& accessor, int index, const std::string& role) const;
  const unsigned char* checked_bytes(int view_index, std::size_t offset, std::size_t stride, std::size_t count,
                                     std::size_t element, int accessor_index, const std::string& role) const;
  const unsigned char* view_data(int view_index, int accessor_index, const std::string& role) const;
  template <typename T>
  std::vector<T> read(const tinygltf::Accessor& accessor, int index, const std::string& role) const;
  template <typename T>
  void apply_sparse(const tinygltf::Accessor& accessor, int index, const std::string& role, std::size_t components,
                    std::vector<T>& values) const;

  const tinygltf::Model& model_;
  std::string path_;
  bool quantization_;  // the file uses KHR_mesh_quantization
  std::map<int, std::vector<float>> substituted_;
  std::map<int, std::vector<std::uint32_t>> substituted_indices_;
  mutable std::map<int, std::vector<unsigned char>> decoded_views_;  // meshopt-compressed views, decoded
};

}  // namespace mbao
