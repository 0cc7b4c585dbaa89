// The order in which work items take the pixels of an image (a render's tile
// is a range of positions in it; HBAO's kernels take the whole image). Blocks
// of 16 x 16 pixels, row by row, each walked in Z order (Morton): the rays of
// neighbouring work items then leave from neighbouring points of the scene and
// walk much the same nodes, which the core still holds in its caches, and any
// aligned run of 4^k positions in a block is a square. Taken row by row, the 64
// pixels of a work group span a strip of a row whose rays share less: on PoCL
// the frames took 0.92-0.93 of the time on Sponza, and no more on any scene
// (docs/traversal.md). Blocks that the image's right or bottom edge
// cuts are walked row by row.
#ifndef MBAO_PIXEL_ORDER_H
#define MBAO_PIXEL_ORDER_H

#include "mbao/platform.h"

#define MBAO_PIXEL_BLOCK 16u  // a power of two

// The even bits of `bits` (0, 2, 4, ...) packed into the low bits.
MBAO_FN mbao_u32 mbao_even_bits(mbao_u32 bits) {
  bits &= 0x55555555u;
  bits = (bits | (bits >> 1)) & 0x33333333u;
  bits = (bits | (bits >> 2)) & 0x0F0F0F0Fu;
  bits = (bits | (bits >> 4)) & 0x00FF00FFu;
  bits = (bits | (bits >> 8)) & 0x0000FFFFu;
  return bits;
}

// The pixel (row by row from the top left) at `position` of the order, for
// position < width * height: every pixel comes once.
MBAO_FN mbao_u32 pixel_at_position(mbao_u32 position, mbao_u32 width, mbao_u32 height) {
  const mbao_u32 band_pixels = MBAO_PIXEL_BLOCK * width;  // a full row of blocks
  const mbao_u32 band = position / band_pixels;
  const mbao_u32 top = band * MBAO_PIXEL_BLOCK;
  const mbao_u32 band_height = height - top < MBAO_PIXEL_BLOCK ? height - top : MBAO_PIXEL_BLOCK;
  const mbao_u32 in_band = position - band * band_pixels;
  const mbao_u32 block_pixels = MBAO_PIXEL_BLOCK * band_height;
  const mbao_u32 left = in_band / block_pixels * MBAO_PIXEL_BLOCK;
  const mbao_u32 in_block = in_band % block_pixels;
  mbao_u32 x, y;
  if (band_height == MBAO_PIXEL_BLOCK && left + MBAO_PIXEL_BLOCK <= width) {
    x = mbao_even_bits(in_block);
    y = mbao_even_bits(in_block >> 1);
  } else {
    // A cut block: the last of its band (its width what the image leaves) or in the last band.
    const mbao_u32 block_width = width - left < MBAO_PIXEL_BLOCK ? width - left : MBAO_PIXEL_BLOCK;
    x = in_block % block_width;
    y = in_block / block_width;
  }
  return (top + y) * width + left + x;
}

#endif
