// The order in which work items take an image's pixels (kernels/mbao/pixel_order.h).
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "device_outputs.h"
#include "mbao/pixel_order.h"
#include "opencl/kernel_sources.h"

namespace mbao {
namespace {

using Xy = std::pair<mbao_u32, mbao_u32>;

Xy pixel_xy(mbao_u32 position, mbao_u32 width, mbao_u32 height) {
  const mbao_u32 pixel = pixel_at_position(position, width, height);
  return {pixel % width, pixel / width};
}

// Every position of the order takes a pixel of the image, and no two the same one.
void expect_each_pixel_once(mbao_u32 width, mbao_u32 height) {
  std::vector<int> taken(std::size_t(width) * height, 0);
  for (mbao_u32 position = 0; position < width * height; ++position) {
    const mbao_u32 pixel = pixel_at_position(position, width, height);
    ASSERT_LT(pixel, width * height) << width << " x " << height << ", position " << position;
    ASSERT_EQ(taken[pixel]++, 0) << width << " x " << height << ": pixel " << pixel << " taken twice";
  }
}

TEST(PixelOrder, TakesEveryPixelOnce) {
  for (mbao_u32 width = 1; width <= 40; ++width)
    for (mbao_u32 height = 1; height <= 40; ++height) expect_each_pixel_once(width, height);
  for (const Xy& size : {Xy{512, 512}, Xy{1920, 1080}, Xy{1000, 1}, Xy{1, 1000}, Xy{257, 255}})
    expect_each_pixel_once(size.first, size.second);
}

TEST(PixelOrder, WalksAWholeBlockInZOrder) {
  const mbao_u32 width = 40, height = 37;
  EXPECT_EQ(pixel_xy(0, width, height), Xy(0, 0));
  EXPECT_EQ(pixel_xy(1, width, height), Xy(1, 0));
  EXPECT_EQ(pixel_xy(2, width, height), Xy(0, 1));
  EXPECT_EQ(pixel_xy(3, width, height), Xy(1, 1));
  EXPECT_EQ(pixel_xy(4, width, height), Xy(2, 0));
  EXPECT_EQ(pixel_xy(255, width, height), Xy(15, 15));
  EXPECT_EQ(pixel_xy(256, width, height), Xy(16, 0));  // the next block of the band
  // Every aligned run of 4^k positions of a block is a 2^k x 2^k square.
  for (mbao_u32 side = 1; side <= MBAO_PIXEL_BLOCK; side *= 2) {
    const mbao_u32 run = side * side;
    for (mbao_u32 first = 0; first < 2 * MBAO_PIXEL_BLOCK * MBAO_PIXEL_BLOCK; first += run) {
      const Xy corner = pixel_xy(first, width, height);
      EXPECT_EQ(corner.first % side, 0u);
      EXPECT_EQ(corner.second % side, 0u);
      for (mbao_u32 k = 0; k < run; ++k) {
        const Xy at = pixel_xy(first + k, width, height);
        EXPECT_TRUE(at.first - corner.first < side && at.second - corner.second < side)
            << "position " << first + k << " outside the " << side << "-square of position " << first;
      }
    }
  }
}

TEST(PixelOrder, WalksCutBlocksRowByRow) {
  const mbao_u32 width = 40, height = 37;  // blocks cut to 8 columns on the right, 5 rows at the bottom
  const mbao_u32 cut_right = 2 * MBAO_PIXEL_BLOCK * MBAO_PIXEL_BLOCK;
  EXPECT_EQ(pixel_xy(cut_right, width, height), Xy(32, 0));
  EXPECT_EQ(pixel_xy(cut_right + 7, width, height), Xy(39, 0));
  EXPECT_EQ(pixel_xy(cut_right + 8, width, height), Xy(32, 1));
  EXPECT_EQ(pixel_xy(cut_right + 8 * 16 - 1, width, height), Xy(39, 15));
  const mbao_u32 last_band = 2 * MBAO_PIXEL_BLOCK * width;
  EXPECT_EQ(pixel_xy(last_band, width, height), Xy(0, 32));
  EXPECT_EQ(pixel_xy(last_band + 15, width, height), Xy(15, 32));
  EXPECT_EQ(pixel_xy(last_band + 16, width, height), Xy(0, 33));
  EXPECT_EQ(pixel_xy(width * height - 1, width, height), Xy(39, 36));
}

TEST(PixelOrder, DeviceWalksTheHostsOrder) {
  const std::string source = kernel_program_source("mbao/pixel_order.h") + R"(
    __kernel void order(uint width, uint height, __global uint* pixels) {
      const uint position = get_global_id(0);
      pixels[position] = pixel_at_position(position, width, height);
    })";
  for (const Xy& size : {Xy{37, 21}, Xy{512, 512}, Xy{1, 33}}) {
    const mbao_u32 n = size.first * size.second;
    const std::vector<cl_uint> device_pixels =
        device_outputs<cl_uint>(source, "order", n, cl_uint(size.first), cl_uint(size.second));
    for (mbao_u32 position = 0; position < n; ++position)
      ASSERT_EQ(device_pixels[position], pixel_at_position(position, size.first, size.second))
          << size.first << " x " << size.second << ", position " << position;
  }
}

}  // namespace
}  // namespace mbao
