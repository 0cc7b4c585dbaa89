#pragma once

#include <cstddef>

#include "opencl/opencl.h"

namespace mbao {

// The work-group size to launch `kernel` with: `requested`, or by default 64
// (a size that suits divergent ray-tracing code on GPUs; a fixed size also
// spares PoCL a compile for every launch size), never more than the kernel
// allows. Throws std::invalid_argument for a request above that limit.
std::size_t work_group_size_for(const cl::Kernel& kernel, const cl::Device& device, std::size_t requested);

// Enqueues `items` work items in groups of `work_group` (at least one group,
// so an empty launch still runs: the kernels return for indices past their count).
void launch(cl::CommandQueue& queue, const cl::Kernel& kernel, std::size_t items, std::size_t work_group);

// Enqueues a columns x rows grid in groups of `work_group` x 1, so that a
// group's work items are neighbouring pixels of one row (at least one group,
// as launch).
void launch_rows(cl::CommandQueue& queue, const cl::Kernel& kernel, std::size_t columns, std::size_t rows,
                 std::size_t work_group);

// Enqueues a read of `bytes` of `buffer` from `offset` into host memory at
// `into`, as enqueueReadBuffer, where a timed queue sees it.
void read_buffer(cl::CommandQueue& queue, const cl::Buffer& buffer, bool blocking, std::size_t offset,
                 std::size_t bytes, void* into);

// Enqueues setting `count` unsigned words of `buffer` to zero, as
// enqueueFillBuffer, where a timed queue sees it.
void zero_words(cl::CommandQueue& queue, const cl::Buffer& buffer, std::size_t count);

// How many rays each work item of a kernel that walks rays in lanes
// (kernels/kd_lanes.h) takes, of `rays` in all: 512 where there are enough,
// fewer where that would leave the device's compute units under four groups
// each, never under 16 (one lane's worth). A lane whose ray ends takes the
// next of its work item's rays, so the more each item has, the longer its
// lanes stay full (on PoCL 512 rays per item gained over 128: docs/traversal.md).
std::size_t rays_per_lane_item(std::size_t rays, const cl::Device& device, std::size_t work_group);

// Launches `kernel`, whose arguments make every work item return at once, on
// one group and on `largest_items` items. Some drivers build a kernel at its
// first launch, for its work-group size and also for the size of its grid
// (PoCL: grids under 65535 items wide and wider ones get builds of their own):
// launched so over the smallest and the largest grid a frame uses, a kernel
// is built before the frame, whatever its tiles' sizes.
void launch_empty(cl::CommandQueue& queue, const cl::Kernel& kernel, std::size_t largest_items, std::size_t work_group);

}  // namespace mbao
