#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mbao {

// The alpha channel of an image, 8 bits per texel, rows from the top.
struct AlphaImage {
  int width = 0;
  int height = 0;
  bool has_alpha = false;            // grey-alpha or RGBA; without, alpha is 1 everywhere
  std::vector<std::uint8_t> alpha;   // width * height values when has_alpha, else empty
};

// Decodes an encoded image (PNG, JPEG, ... with 8 or 16 bits per channel)
// keeping only its alpha. Throws LoadError naming `what` when it cannot.
AlphaImage decode_alpha(const unsigned char* bytes, std::size_t size, const std::string& what);

}  // namespace mbao
