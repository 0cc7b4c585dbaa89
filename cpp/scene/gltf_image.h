// Images as a glTF file may hold them (image/png or image/jpeg): what bake_file
// writes a base colour image of another format's material as.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mbao {

// `bytes` of an encoded image as PNG or JPEG bytes: PNG and JPEG as they are,
// any other format stb_image decodes (TGA, BMP, PSD, GIF, HDR, PNM) encoded as
// an 8-bit PNG with its channels. Throws LoadError naming `what` where it
// cannot decode, or check_image_texels refuses the image.
std::vector<unsigned char> png_or_jpeg(const unsigned char* bytes, std::size_t size, const std::string& what);

// Throws LoadError naming `what` for an image of more than 2^28 texels (16384 x 16384), the most a mask
// texture may have too: checked from its size, before its texels' memory is taken.
void check_image_texels(std::size_t width, std::size_t height, const std::string& what);

// A PNG of width x height RGBA texels, rows from the top.
std::vector<unsigned char> png_of_rgba(const std::uint8_t* rgba, int width, int height);

}  // namespace mbao
