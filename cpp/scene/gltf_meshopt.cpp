#include "scene/gltf_meshopt.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace mbao {
namespace {

constexpr const char* kExtension = "EXT_meshopt_compression";
constexpr std::size_t kMaxRatio = 64;

// A view's extension fields, checked.
struct Encoding {
  const std::vector<unsigned char>* buffer = nullptr;
  std::size_t offset = 0, length = 0, stride = 0, count = 0;
  std::string mode, filter;
};

// The extension's field `key`: `fallback` where absent; a number beyond 2^53 (JSON's integers are doubles) as
// the largest size, which every check below refuses.
std::size_t whole(const tinygltf::Value& object, const char* key, std::size_t fallback, const std::string& what) {
  if (!object.Has(key)) return fallback;
  const tinygltf::Value& value = object.Get(key);
  const double number = value.IsNumber() ? value.GetNumberAsDouble() : -1.0;
  if (!(number >= 0.0) || number != std::floor(number))
    throw LoadError(what + ": " + key + " is not a whole number of 0 or more");
  return number < 9007199254740992.0 ? std::size_t(number) : std::numeric_limits<std::size_t>::max();
}

Encoding encoding_of(const tinygltf::Model& model, const tinygltf::Value& extension, const std::string& what) {
  Encoding e;
  const std::size_t buffer = whole(extension, "buffer", model.buffers.size(), what);
  if (buffer >= model.buffers.size()) throw LoadError(what + " names no buffer of the file");
  e.buffer = &model.buffers[buffer].data;
  e.offset = whole(extension, "byteOffset", 0, what);
  e.length = whole(extension, "byteLength", 0, what);
  e.stride = whole(extension, "byteStride", 0, what);
  e.count = whole(extension, "count", 0, what);
  e.mode = extension.Get("mode").IsString() ? extension.Get("mode").Get<std::string>() : "";
  e.filter = extension.Get("filter").IsString() ? extension.Get("filter").Get<std::string>() : "NONE";
  if (e.offset > e.buffer->size() || e.length > e.buffer->size() - e.offset)
    throw LoadError(what + " runs past the end of buffer " + std::to_string(buffer));
  // meshoptimizer's densest encoding (a 2-bit header per 16 bytes that are all alike) decodes to at most 64
  // times its bytes: a count beyond that is a lie, refused before its memory is allocated.
  if (e.stride == 0 || e.count > kMaxRatio * std::min(e.length + 1, e.buffer->size()) / e.stride)
    throw LoadError(what + " has byteStride " + std::to_string(e.stride) + " and count " + std::to_string(e.count) +
                    ", more than its " + std::to_string(e.length) + " encoded bytes can hold");
  return e;
}

// The extension's rules on a mode's and a filter's strides and counts, which
// meshoptimizer's decoders assert rather than check.
void check_layout(const Encoding& e, const std::string& what) {
  const std::string stride = "byteStride " + std::to_string(e.stride);
  const bool index_mode = e.mode == "TRIANGLES" || e.mode == "INDICES";
  if (e.mode == "ATTRIBUTES" && (e.stride % 4 != 0 || e.stride > 256))
    throw LoadError(what + " has mode ATTRIBUTES and " + stride + "; it must be a multiple of 4 up to 256");
  if (index_mode && e.stride != 2 && e.stride != 4)
    throw LoadError(what + " has mode " + e.mode + " and " + stride + "; it must be 2 or 4");
  if (index_mode && e.filter != "NONE")
    throw LoadError(what + " has mode " + e.mode + " and filter " + e.filter + "; index modes take no filter");
  if (e.mode == "TRIANGLES" && e.count % 3 != 0)
    throw LoadError(what + " has mode TRIANGLES and count " + std::to_string(e.count) + ", not a multiple of 3");
  const bool filter_fits = e.filter == "OCTAHEDRAL"    ? e.stride == 4 || e.stride == 8
                           : e.filter == "QUATERNION"  ? e.stride == 8
                           : e.filter == "EXPONENTIAL" ? e.stride % 4 == 0
                                                       : true;
  if (!filter_fits)
    throw LoadError(what + " has filter " + e.filter + " and " + stride +
                    "; OCTAHEDRAL takes 4 or 8, QUATERNION 8, EXPONENTIAL a multiple of 4");
}

// meshoptimizer's decoder for the mode, and its filter: 0 on success.
int decode(const Encoding& e, unsigned char* out) {
  const unsigned char* source = e.buffer->data() + e.offset;
  if (e.mode == "TRIANGLES") return meshopt_decodeIndexBuffer(out, e.count, e.stride, source, e.length);
  if (e.mode == "INDICES") return meshopt_decodeIndexSequence(out, e.count, e.stride, source, e.length);
  const int status = meshopt_decodeVertexBuffer(out, e.count, e.stride, source, e.length);
  if (status == 0 && e.filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out, e.count, e.stride);
  if (status == 0 && e.filter == "QUATERNION") meshopt_decodeFilterQuat(out, e.count, e.stride);
  if (status == 0 && e.filter == "EXPONENTIAL") meshopt_decodeFilterExp(out, e.count, e.stride);
  return status;
}

}  // namespace

std::optional<std::vector<unsigned char>> decoded_meshopt_view(const tinygltf::Model& model, int view_index,
                                                               const std::string& path) {
  const tinygltf::BufferView& view = model.bufferViews[std::size_t(view_index)];
  const auto found = view.extensions.find(kExtension);
  if (found == view.extensions.end()) return std::nullopt;
  const std::string what = path + ": bufferView " + std::to_string(view_index) + " " + kExtension;
  const Encoding e = encoding_of(model, found->second, what);
  const bool known_mode = e.mode == "ATTRIBUTES" || e.mode == "TRIANGLES" || e.mode == "INDICES";
  const bool known_filter =
      e.filter == "NONE" || e.filter == "OCTAHEDRAL" || e.filter == "QUATERNION" || e.filter == "EXPONENTIAL";
  if (!known_mode || !known_filter)
    throw LoadError(what + " has mode \"" + e.mode + "\" and filter \"" + e.filter +
                    "\"; the extension defines ATTRIBUTES, TRIANGLES and INDICES, and NONE, OCTAHEDRAL, "
                    "QUATERNION and EXPONENTIAL");
  check_layout(e, what);
  std::vector<unsigned char> bytes(e.count * e.stride);
  if (decode(e, bytes.data()) != 0) throw LoadError(what + ": its " + e.mode + " data does not decode");
  return bytes;
}

}  // namespace mbao
