// The G-buffer (SPEC 7.2): for each pixel the hit of the ray through its
// centre, as every screen-space pass reads it (HBAO, the spatial filter,
// temporal accumulation). Shared by the host, which reads it back and fills
// test buffers with it, and the kernels.
//
// It is stored as planes, each one quantity for every pixel row by row, so
// that work items of neighbouring pixels read neighbouring floats: coalesced
// loads on a GPU, and on PoCL the only layout whose loop over work items the
// compiler turns into vector loads (a texel struct per pixel gets gathers).
// A frame's G-buffer holds the planes of one set, that of the passes that
// read it, in plane order and with no room for the others.
#ifndef MBAO_GBUFFER_H
#define MBAO_GBUFFER_H

#include "mbao/platform.h"

// A pixel that no triangle covers: every plane 0 but the triangle's.
#define MBAO_GBUFFER_NO_TRIANGLE 0xFFFFFFFFu

typedef struct GBufferTexel {
  float x, y, z;      // the hit point, in the scene's device frame (relative to its render origin)
  float t;            // its distance along the camera ray; 0 where the ray missed
  float nx, ny, nz;   // the geometric normal, turned to the eye
  float footprint;    // the side of the pixel at distance t: 2 t tan(vfov / 2) / height
  float depth;        // its distance along the view direction (view-space z); 0 where the ray missed
  float sx, sy, sz;   // the shading normal (SPEC 3.3), turned to the eye
  mbao_u32 triangle;  // the hit triangle's index, MBAO_GBUFFER_NO_TRIANGLE where the ray missed
} GBufferTexel;

// The planes, in GBufferTexel's order. The triangle plane holds its indices' bits.
enum GBufferPlane {
  GBUFFER_X,
  GBUFFER_Y,
  GBUFFER_Z,
  GBUFFER_T,
  GBUFFER_NX,
  GBUFFER_NY,
  GBUFFER_NZ,
  GBUFFER_FOOTPRINT,
  GBUFFER_DEPTH,
  GBUFFER_SX,
  GBUFFER_SY,
  GBUFFER_SZ,
  GBUFFER_TRIANGLE,
  GBUFFER_PLANES
};

// Sets of planes, as masks of 1 << plane: what each reader reads. A frame's
// camera rays write the planes its readers need and no others, since on a CPU
// writing the planes, not making the texel, is most of what a texel costs.
#define MBAO_GBUFFER_PLANE(plane) (1u << (plane))
#define MBAO_GBUFFER_HBAO_PLANES                                                                         \
  (MBAO_GBUFFER_PLANE(GBUFFER_DEPTH) | MBAO_GBUFFER_PLANE(GBUFFER_SX) | MBAO_GBUFFER_PLANE(GBUFFER_SY) | \
   MBAO_GBUFFER_PLANE(GBUFFER_SZ))
// The spatial filter's and temporal accumulation's: the point, t, the geometric normal and the footprint.
#define MBAO_GBUFFER_FILTER_PLANES (MBAO_GBUFFER_PLANE(GBUFFER_DEPTH) - 1u)
#define MBAO_GBUFFER_ALL_PLANES (MBAO_GBUFFER_PLANE(GBUFFER_PLANES) - 1u)

// How many planes a G-buffer of `set` holds.
MBAO_FN mbao_u32 gbuffer_plane_count(mbao_u32 set) { return (mbao_u32)mbao_popcount(set); }

// Where plane `plane` starts in a G-buffer of `pixels` pixels that holds the
// planes of `set`: after those of the set's planes that come before it.
MBAO_FN mbao_u64 gbuffer_plane_offset(mbao_u32 pixels, mbao_u32 set, enum GBufferPlane plane) {
  return (mbao_u64)gbuffer_plane_count(set & (MBAO_GBUFFER_PLANE(plane) - 1u)) * pixels;
}

// Plane `plane`, of `set`, of a G-buffer of `pixels` pixels that holds the planes of `set`.
MBAO_FN const MBAO_GLOBAL float* gbuffer_plane(const MBAO_GLOBAL float* gbuffer, mbao_u32 pixels, mbao_u32 set,
                                               enum GBufferPlane plane) {
  return gbuffer + gbuffer_plane_offset(pixels, set, plane);
}

// A plane of a frame's G-buffer for the filters (SPEC 7.3, 7.4), and of one for HBAO.
MBAO_FN const MBAO_GLOBAL float* filter_gbuffer_plane(const MBAO_GLOBAL float* gbuffer, mbao_u32 pixels,
                                                      enum GBufferPlane plane) {
  return gbuffer_plane(gbuffer, pixels, MBAO_GBUFFER_FILTER_PLANES, plane);
}
MBAO_FN const MBAO_GLOBAL float* hbao_gbuffer_plane(const MBAO_GLOBAL float* gbuffer, mbao_u32 pixels,
                                                    enum GBufferPlane plane) {
  return gbuffer_plane(gbuffer, pixels, MBAO_GBUFFER_HBAO_PLANES, plane);
}

// Stores the planes of `g` that `planes` names (MBAO_GBUFFER_PLANE masks)
// into a G-buffer that holds those planes.
MBAO_FN void gbuffer_store(MBAO_GLOBAL float* gbuffer, mbao_u32 pixels, mbao_u32 pixel, GBufferTexel g,
                           mbao_u32 planes) {
  const float fields[GBUFFER_PLANES] = {
      g.x, g.y, g.z, g.t, g.nx, g.ny, g.nz, g.footprint, g.depth, g.sx, g.sy, g.sz, mbao_u32_as_float(g.triangle)};
  mbao_u64 at = pixel;  // in the next plane of the set
  MBAO_UNROLL
  for (int plane = 0; plane < GBUFFER_PLANES; ++plane) {
    if (planes & MBAO_GBUFFER_PLANE(plane)) {
      gbuffer[at] = fields[plane];
      at += pixels;
    }
  }
}

#endif
