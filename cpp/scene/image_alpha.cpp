#include "scene/image_alpha.h"

#include <stb/stb_image.h>

#include <climits>
#include <memory>
#include <string>

#include "core/error.h"

namespace mbao {
namespace {

struct StbFree {
  void operator()(void* pixels) const { stbi_image_free(pixels); }
};

// Channel `channel` of every texel, rescaled to 8 bits.
template <typename T>
std::vector<std::uint8_t> one_channel(const T* pixels, std::size_t texels, int channels, int channel, unsigned max) {
  std::vector<std::uint8_t> alpha(texels);
  for (std::size_t i = 0; i < texels; ++i)
    alpha[i] =
        std::uint8_t((unsigned(pixels[i * std::size_t(channels) + std::size_t(channel)]) * 255u + max / 2) / max);
  return alpha;
}

}  // namespace

void check_alpha_texels(std::size_t width, std::size_t height, const std::string& what) {
  if (width * height > kMaxAlphaTexels)
    throw LoadError(what + ": the image is " + std::to_string(width) + " x " + std::to_string(height) +
                    " texels; a mask texture may have at most 2^28 (16384 x 16384)");
}

AlphaImage decode_alpha(const unsigned char* bytes, std::size_t size, const std::string& what,
                        bool first_channel_without_alpha) {
  if (size == 0 || size > std::size_t(INT_MAX)) throw LoadError(what + ": image data is empty or too large");
  const int length = int(size);
  AlphaImage image;
  int channels = 0;
  if (!stbi_info_from_memory(bytes, length, &image.width, &image.height, &channels))
    throw LoadError(what + ": cannot decode the image (" + stbi_failure_reason() + ")");
  const bool alpha_channel = channels == 2 || channels == 4;
  image.has_alpha = alpha_channel || first_channel_without_alpha;
  if (!image.has_alpha) return image;  // alpha 1 everywhere: no texels needed
  const int channel = alpha_channel ? channels - 1 : 0;
  check_alpha_texels(std::size_t(image.width), std::size_t(image.height), what);
  const std::size_t texels = std::size_t(image.width) * std::size_t(image.height);
  int w = 0, h = 0;
  // The alpha is read for the size and channels stbi_info reported, so the decoded image must have them.
  const auto check_decoded = [&](const void* pixels) {
    if (!pixels) throw LoadError(what + ": cannot decode the image (" + stbi_failure_reason() + ")");
    if (w != image.width || h != image.height || (channels == 2 || channels == 4) != alpha_channel)
      throw LoadError(what + ": the image decodes to another size or channel count than its header gives");
  };
  if (stbi_is_16_bit_from_memory(bytes, length)) {
    std::unique_ptr<stbi_us, StbFree> pixels(stbi_load_16_from_memory(bytes, length, &w, &h, &channels, 0));
    check_decoded(pixels.get());
    image.alpha = one_channel(pixels.get(), texels, channels, channel, 65535u);
  } else {
    std::unique_ptr<stbi_uc, StbFree> pixels(stbi_load_from_memory(bytes, length, &w, &h, &channels, 0));
    check_decoded(pixels.get());
    image.alpha = one_channel(pixels.get(), texels, channels, channel, 255u);
  }
  return image;
}

}  // namespace mbao
