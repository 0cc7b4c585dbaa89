// One pixel of the G-buffer (SPEC 7.2): the hit of the ray through the pixel
// centre, as the screen-space passes read it. Shared by the host, which sizes
// and fills test buffers with it, and the kernels.
#ifndef MBAO_GBUFFER_H
#define MBAO_GBUFFER_H

#include "mbao/platform.h"

typedef struct GBufferTexel {
  float x, y, z;       // the hit point, in the scene's device frame (relative to its render origin)
  float t;             // its distance along the camera ray; 0 where the ray missed
  float nx, ny, nz;    // the geometric normal, turned to the eye
  float footprint;     // the side of the pixel at distance t: 2 t tan(vfov / 2) / height
} GBufferTexel;

#endif
