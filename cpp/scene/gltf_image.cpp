#include "scene/gltf_image.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <climits>
#include <cstring>
#include <memory>

#include "core/error.h"
#include "scene/image_alpha.h"

namespace mbao {
namespace {

bool starts_with(const unsigned char* bytes, std::size_t size, const char* magic, std::size_t length) {
  return size >= length && std::memcmp(bytes, magic, length) == 0;
}

void append(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
}

std::vector<unsigned char> png_of(const std::uint8_t* texels, int width, int height, int channels) {
  std::vector<unsigned char> png;
  if (!stbi_write_png_to_func(append, &png, width, height, channels, texels, width * channels))
    throw LoadError("cannot encode a " + std::to_string(width) + " x " + std::to_string(height) + " image as PNG");
  return png;
}

struct StbFree {
  void operator()(void* pixels) const { stbi_image_free(pixels); }
};

}  // namespace

void check_image_texels(std::size_t width, std::size_t height, const std::string& what) {
  if (width * height > kMaxAlphaTexels)
    throw LoadError(what + ": the image is " + std::to_string(width) + " x " + std::to_string(height) +
                    " texels; one kept for a glTF file may have at most 2^28 (16384 x 16384)");
}

std::vector<unsigned char> png_or_jpeg(const unsigned char* bytes, std::size_t size, const std::string& what) {
  if (starts_with(bytes, size, "\x89PNG\r\n\x1a\n", 8) || starts_with(bytes, size, "\xff\xd8\xff", 3))
    return {bytes, bytes + size};
  if (size > std::size_t(INT_MAX)) throw LoadError(what + ": the image file is over 2 GiB");
  int width = 0, height = 0, channels = 0;
  if (!stbi_info_from_memory(bytes, int(size), &width, &height, &channels))
    throw LoadError(what + ": cannot decode the image (" + stbi_failure_reason() + ")");
  check_image_texels(std::size_t(width), std::size_t(height), what);
  const std::unique_ptr<stbi_uc, StbFree> texels(
      stbi_load_from_memory(bytes, int(size), &width, &height, &channels, 0));
  if (!texels) throw LoadError(what + ": cannot decode the image (" + stbi_failure_reason() + ")");
  return png_of(texels.get(), width, height, channels);
}

std::vector<unsigned char> png_of_rgba(const std::uint8_t* rgba, int width, int height) {
  return png_of(rgba, width, height, 4);
}

}  // namespace mbao
