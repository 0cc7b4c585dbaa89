// The wavefront organisation's queue entry, shared so that the host sizes the
// queues with the kernels' layout.
#ifndef MBAO_WAVEFRONT_H
#define MBAO_WAVEFRONT_H

#include "mbao/platform.h"

// A surface that the next bounce leaves from, kept as the hit that made it and
// the direction of the ray that hit it: make_surface then rebuilds exactly the
// surface the megakernel builds, in 32 bytes instead of a Surface's 64.
typedef struct QueuedSurface {
  mbao_u32 triangle;
  float b1, b2;
  float incoming_x, incoming_y, incoming_z;
  mbao_u32 sample;  // camera sample within the tile: pixel index * spp + camera sample
  mbao_u32 node;    // the ray's node in the estimator's tree, which keys its children's random numbers
} QueuedSurface;

#endif
