// The alpha lookup the kernels run (kernels/mbao/alpha_mask.h), here on the host.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "mbao/alpha_mask.h"

namespace mbao {
namespace {

MaskTexture texture(std::uint32_t width, std::uint32_t height, std::uint32_t wrap_s, std::uint32_t wrap_t) {
  MaskTexture t{};
  t.width = width;
  t.height = height;
  t.wrap = wrap_s | (wrap_t << 2);
  t.alpha_factor = 1.0f;
  t.cutoff = 0.5f;
  return t;
}

// Two texels in a row: transparent, then opaque.
const std::vector<std::uint8_t> kTwoTexels = {0, 255};

TEST(AlphaMask, BilinearBetweenTexelCentres) {
  const MaskTexture t = texture(2, 1, MBAO_WRAP_CLAMP_TO_EDGE, MBAO_WRAP_CLAMP_TO_EDGE);
  EXPECT_FLOAT_EQ(mask_alpha(t, kTwoTexels.data(), 0.25f, 0.5f), 0.0f);  // centre of texel 0
  EXPECT_FLOAT_EQ(mask_alpha(t, kTwoTexels.data(), 0.75f, 0.5f), 1.0f);  // centre of texel 1
  EXPECT_FLOAT_EQ(mask_alpha(t, kTwoTexels.data(), 0.5f, 0.5f), 0.5f);   // half way
  EXPECT_FLOAT_EQ(mask_alpha(t, kTwoTexels.data(), 0.375f, 0.5f), 0.25f);
}

TEST(AlphaMask, WrapModes) {
  const MaskTexture clamp = texture(2, 1, MBAO_WRAP_CLAMP_TO_EDGE, MBAO_WRAP_REPEAT);
  EXPECT_FLOAT_EQ(mask_alpha(clamp, kTwoTexels.data(), -3.0f, 0.5f), 0.0f);
  EXPECT_FLOAT_EQ(mask_alpha(clamp, kTwoTexels.data(), 7.0f, 0.5f), 1.0f);
  const MaskTexture repeat = texture(2, 1, MBAO_WRAP_REPEAT, MBAO_WRAP_REPEAT);
  EXPECT_FLOAT_EQ(mask_alpha(repeat, kTwoTexels.data(), 0.0f, 0.5f), 0.5f);  // the seam blends last and first
  EXPECT_FLOAT_EQ(mask_alpha(repeat, kTwoTexels.data(), 5.25f, 0.5f), 0.0f);
  EXPECT_FLOAT_EQ(mask_alpha(repeat, kTwoTexels.data(), -4.25f, 0.5f), 1.0f);
  const MaskTexture mirrored = texture(2, 1, MBAO_WRAP_MIRRORED_REPEAT, MBAO_WRAP_REPEAT);
  EXPECT_FLOAT_EQ(mask_alpha(mirrored, kTwoTexels.data(), 1.25f, 0.5f), 1.0f);  // u in [1, 2] reads 2 - u
  EXPECT_FLOAT_EQ(mask_alpha(mirrored, kTwoTexels.data(), 1.75f, 0.5f), 0.0f);
  EXPECT_FLOAT_EQ(mask_alpha(mirrored, kTwoTexels.data(), 1.0f, 0.5f), 1.0f);  // no seam at the mirror
}

TEST(AlphaMask, RowsRunFromTheTopOfTheImage) {
  const std::vector<std::uint8_t> column = {255, 0};  // top row opaque
  const MaskTexture t = texture(1, 2, MBAO_WRAP_CLAMP_TO_EDGE, MBAO_WRAP_CLAMP_TO_EDGE);
  EXPECT_FLOAT_EQ(mask_alpha(t, column.data(), 0.5f, 0.25f), 1.0f);
  EXPECT_FLOAT_EQ(mask_alpha(t, column.data(), 0.5f, 0.75f), 0.0f);
}

TEST(AlphaMask, FactorAndCutoffDecide) {
  MaskTexture t = texture(2, 1, MBAO_WRAP_CLAMP_TO_EDGE, MBAO_WRAP_CLAMP_TO_EDGE);
  MaskedTriangle triangle{};
  const float uv[6] = {0.75f, 0.5f, 0.75f, 0.5f, 0.75f, 0.5f};  // every point samples texel 1
  for (int i = 0; i < 6; ++i) triangle.uv[i] = uv[i];
  EXPECT_TRUE(mask_is_opaque(triangle, t, kTwoTexels.data(), 0.2f, 0.3f));
  t.alpha_factor = 0.4f;  // 0.4 * 1 < 0.5
  EXPECT_FALSE(mask_is_opaque(triangle, t, kTwoTexels.data(), 0.2f, 0.3f));
  t.cutoff = 0.4f;  // alpha equal to the cutoff is opaque
  EXPECT_TRUE(mask_is_opaque(triangle, t, kTwoTexels.data(), 0.2f, 0.3f));
}

}  // namespace
}  // namespace mbao
