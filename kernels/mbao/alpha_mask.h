// Alpha masks (SPEC 3.2) as host and device share them. A triangle of a MASK
// material is transparent where baseColorFactor.a * texture alpha, sampled
// bilinearly with the sampler's wrap modes, is below alphaCutoff.
#ifndef MBAO_ALPHA_MASK_H
#define MBAO_ALPHA_MASK_H

#include "mbao/platform.h"

#define MBAO_NOT_MASKED 0xFFFFFFFFu

// glTF wrap modes, as stored in MaskTexture.wrap (s in bits 0-1, t in bits 2-3).
#define MBAO_WRAP_REPEAT 0u
#define MBAO_WRAP_CLAMP_TO_EDGE 1u
#define MBAO_WRAP_MIRRORED_REPEAT 2u

// One alpha texture: 8-bit alpha, row-major from the image's top row, at
// first_texel in the shared texel array.
typedef struct MaskTexture {
  mbao_u32 first_texel;
  mbao_u32 width;
  mbao_u32 height;
  mbao_u32 wrap;
  float alpha_factor;  // baseColorFactor.a
  float cutoff;        // alphaCutoff
  mbao_u32 padding[2];
} MaskTexture;

// A triangle of a MASK material: its texture coordinates at the corners.
typedef struct MaskedTriangle {
  float uv[6];
  mbao_u32 texture;  // index into the MaskTexture array
  mbao_u32 padding;
} MaskedTriangle;

// A texel index wrapped into [0, n) as the glTF sampler says.
MBAO_FN int mask_wrap_texel(int i, int n, mbao_u32 mode) {
  if (mode == MBAO_WRAP_CLAMP_TO_EDGE) return i < 0 ? 0 : (i >= n ? n - 1 : i);
  if (mode == MBAO_WRAP_MIRRORED_REPEAT) {
    const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
    return m < n ? m : 2 * n - 1 - m;
  }
  return ((i % n) + n) % n;
}

// A texture coordinate reduced to one period of its wrap mode, so that the
// texel arithmetic stays in range for any coordinate.
MBAO_FN float mask_reduce_coordinate(float s, mbao_u32 mode) {
  if (mode == MBAO_WRAP_CLAMP_TO_EDGE) return s < 0.0f ? 0.0f : (s > 1.0f ? 1.0f : s);
  if (mode == MBAO_WRAP_MIRRORED_REPEAT) return s - 2.0f * mbao_floor(0.5f * s);
  return s - mbao_floor(s);
}

// baseColorFactor.a times the texture's alpha at (u, v), bilinear between the
// four texels around it (texel centres at half-integers, as in glTF/OpenGL).
MBAO_FN float mask_alpha(MaskTexture texture, MBAO_GLOBAL const mbao_u8* texels, float u, float v) {
  const int w = (int)texture.width, h = (int)texture.height;
  const mbao_u32 wrap_s = texture.wrap & 3u, wrap_t = (texture.wrap >> 2) & 3u;
  const float x = mask_reduce_coordinate(u, wrap_s) * (float)w - 0.5f;
  const float y = mask_reduce_coordinate(v, wrap_t) * (float)h - 0.5f;
  const float x0 = mbao_floor(x), y0 = mbao_floor(y);
  const float fx = x - x0, fy = y - y0;
  const int i0 = mask_wrap_texel((int)x0, w, wrap_s), i1 = mask_wrap_texel((int)x0 + 1, w, wrap_s);
  const int j0 = mask_wrap_texel((int)y0, h, wrap_t), j1 = mask_wrap_texel((int)y0 + 1, h, wrap_t);
  MBAO_GLOBAL const mbao_u8* image = texels + texture.first_texel;
  const float a00 = image[j0 * w + i0], a10 = image[j0 * w + i1];
  const float a01 = image[j1 * w + i0], a11 = image[j1 * w + i1];
  const float top = a00 + fx * (a10 - a00), bottom = a01 + fx * (a11 - a01);
  return texture.alpha_factor * (top + fy * (bottom - top)) * (1.0f / 255.0f);
}

// Whether a hit at barycentrics (b1, b2) of a masked triangle is solid.
MBAO_FN int mask_is_opaque(MaskedTriangle triangle, MaskTexture texture, MBAO_GLOBAL const mbao_u8* texels, float b1,
                           float b2) {
  const float b0 = 1.0f - b1 - b2;
  const float u = b0 * triangle.uv[0] + b1 * triangle.uv[2] + b2 * triangle.uv[4];
  const float v = b0 * triangle.uv[1] + b1 * triangle.uv[3] + b2 * triangle.uv[5];
  return mask_alpha(texture, texels, u, v) >= texture.cutoff;
}

#endif
