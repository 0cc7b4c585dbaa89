#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "opencl/opencl.h"
#include "render/ao_kernel_args.h"
#include "render/device_scene.h"
#include "render/render_plan.h"
#include "render/render_settings.h"
#include "render/streamed_bounces.h"

namespace mbao {

// The branching estimator as a wavefront (render.cl's wavefront_* kernels, kernels/render/wavefront_bounces.h):
// bounce 1 over the tile's camera samples, each further bounce over the queue
// of surfaces the bounce before filled, then one work item per pixel weighs
// the escapes. Two queues take turns, so a tile holds at most
// tile_pixels * spp * max_queue_entries_per_camera_sample() entries. With
// traversal "lanes" each bounce runs as StreamedBounces instead, with the same
// counts and queues.
class Wavefront {
 public:
  // kernels: the plan's wavefront kernels (first_bounce, bounce, finish), or its streamed ones.
  Wavefront(const cl::Context& context, const cl::Device& device, const cl::Program& program, const DeviceScene& scene,
            const AoArgs& ao_args, const RenderSettings& settings, const FrameKernels& kernels, std::size_t tile_pixels,
            const FrameBuffers& frame);

  // AO for pixels [first, first + count), whose camera hits the frame holds.
  // Blocks until each queue is filled: its length sizes the launch that reads it.
  void enqueue_tile(cl::CommandQueue& queue, std::size_t first, std::size_t count);
  // Frame::enqueue_empty_tiles's part: each kernel launched over no pixels, on
  // the smallest grid and on the largest a tile of tile_pixels may launch it on.
  void enqueue_empty_tiles(cl::CommandQueue& queue, std::size_t tile_pixels);

  std::size_t bytes() const { return bytes_; }
  // What the constructor will allocate for these settings and tile size.
  static std::size_t device_bytes(const RenderSettings& settings, const FrameKernels& kernels, std::size_t tile_pixels);
  // The kernels and their work-group sizes, for Frame::launch_signature().
  std::string launch_signature() const;

 private:
  struct BufferSizes {
    std::size_t escape_counts, sample_rays, queue_lengths, queues[2];
    std::size_t longest_queue;  // entries
    std::size_t max_sources;    // of a bounce: the tile's camera samples or a queue's entries
    std::size_t streams;        // StreamedBounces', with traversal "lanes"
    std::size_t total() const { return escape_counts + sample_rays + queue_lengths + queues[0] + queues[1] + streams; }
  };
  static BufferSizes buffer_sizes(const RenderSettings& settings, const FrameKernels& kernels, std::size_t tile_pixels);
  void enqueue_bounces(cl::CommandQueue& queue, std::size_t tile_samples);
  void enqueue_streamed_bounces(cl::CommandQueue& queue, std::size_t tile_samples);

  // The queue that bounce `bounce` fills; null where no bounce fills it.
  const cl::Buffer& queue_of(std::size_t bounce) const { return queues_[bounce % 2]; }
  std::size_t queue_length(cl::CommandQueue& queue, std::size_t bounce) const;
  // Empties every queue and points the kernels at pixels [first, first + count).
  void start_tile(cl::CommandQueue& queue, std::size_t first, std::size_t count);
  // Points the bounce kernel at bounce `bounce`: the queue it reads and the one it fills.
  void set_bounce(std::size_t bounce);

  const DeviceScene& scene_;
  const AoArgs ao_args_;
  const FrameBuffers frame_;
  std::size_t spp_, bounces_;
  std::size_t first_position_ = 0;  // the tile's
  std::size_t longest_queue_ = 0;   // entries, the larger queue's
  cl::Buffer escape_counts_, sample_rays_, queue_lengths_;
  cl::Buffer queues_[2];
  cl::Kernel first_bounce_, bounce_, finish_;
  std::size_t first_bounce_group_ = 0, bounce_group_ = 0, finish_group_ = 0;
  std::unique_ptr<StreamedBounces> streams_;  // traversal "lanes": these bounce kernels, not the two above
  std::size_t bytes_ = 0;
};

}  // namespace mbao
