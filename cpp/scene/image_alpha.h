#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"

namespace mbao {

// The alpha channel of an image, 8 bits per texel, rows from the top.
struct AlphaImage {
  int width = 0;
  int height = 0;
  bool has_alpha = false;           // grey-alpha or RGBA; without, alpha is 1 everywhere
  std::vector<std::uint8_t> alpha;  // width * height values when has_alpha, else empty
};

// The most texels a mask image may have: 16384 x 16384, the largest texture
// size GPUs take. Checked from the image's header, before anything is decoded,
// so a small file that declares a huge image is refused without the memory.
constexpr std::size_t kMaxAlphaTexels = std::size_t(1) << 28;

// Throws LoadError naming `what` for an image of more texels than kMaxAlphaTexels.
void check_alpha_texels(std::size_t width, std::size_t height, const std::string& what);

// Decodes an encoded image (PNG, JPEG, ... with 8 or 16 bits per channel)
// keeping only its alpha; with `first_channel_without_alpha`, an image
// without alpha gives its first channel instead (an OBJ opacity map is a
// grey image). Throws LoadError naming `what` when it cannot.
AlphaImage decode_alpha(const unsigned char* bytes, std::size_t size, const std::string& what,
                        bool first_channel_without_alpha = false);

// read()'s image, or none where it throws LoadError (a mask image that is
// missing, unreadable or undecodable): then the error, with what follows from
// it, joins `warnings`, and the surface is opaque (SPEC 3.2).
template <typename Read>
std::optional<AlphaImage> alpha_unless_unreadable(Read read, std::vector<std::string>& warnings) {
  try {
    return read();
  } catch (const LoadError& e) {
    warnings.push_back(std::string(e.what()) + "; the surface is opaque");
    return std::nullopt;
  }
}

}  // namespace mbao
