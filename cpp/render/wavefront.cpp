#include "render/wavefront.h"

#include <algorithm>
#include <cstdint>

#include "mbao/wavefront.h"
#include "opencl/launch.h"

namespace mbao {
namespace {

// Entries that queue `parity` holds at most per camera sample: r^k for the
// deepest bounce k < b of that parity, as the bounces of one parity take turns in it.
std::size_t queue_entries_per_camera_sample(const RenderSettings& s, std::int64_t parity) {
  std::size_t deepest = 0, level = 1;
  for (std::int64_t k = 1; k < s.bounces; ++k) {
    level *= std::size_t(s.samples);
    if (k % 2 == parity) deepest = level;
  }
  return deepest;
}

}  // namespace

Wavefront::BufferSizes Wavefront::buffer_sizes(const RenderSettings& s, std::size_t tile_pixels) {
  const std::size_t tile_samples = tile_pixels * std::size_t(s.spp);
  BufferSizes sizes;
  sizes.escape_counts = tile_samples * std::size_t(s.bounces) * sizeof(cl_uint);
  sizes.sample_rays = tile_samples * sizeof(cl_uint);
  sizes.queue_lengths = (std::size_t(s.bounces) + 1) * sizeof(cl_uint);
  for (std::int64_t parity : {0, 1})
    sizes.queues[parity] = tile_samples * queue_entries_per_camera_sample(s, parity) * sizeof(QueuedSurface);
  sizes.longest_queue = std::max(sizes.queues[0], sizes.queues[1]) / sizeof(QueuedSurface);
  sizes.max_sources = std::max(tile_samples, sizes.longest_queue);
  sizes.streams = s.traversal == Traversal::Lanes ? StreamedBounces::device_bytes(s, sizes.max_sources) : 0;
  return sizes;
}

std::size_t Wavefront::device_bytes(const RenderSettings& s, std::size_t tile_pixels) {
  return buffer_sizes(s, tile_pixels).total();
}

Wavefront::Wavefront(const cl::Context& context, const cl::Device& device, const cl::Program& program,
                     const DeviceScene& scene, const Camera& camera, const RenderSettings& s,
                     std::size_t tile_pixels, const FrameBuffers& frame)
    : spp_(std::size_t(s.spp)), bounces_(std::size_t(s.bounces)) {
  const BufferSizes sizes = buffer_sizes(s, tile_pixels);
  const auto allocate = [&](std::size_t bytes) {
    return bytes ? cl::Buffer(context, CL_MEM_READ_WRITE, bytes) : cl::Buffer();
  };
  escape_counts_ = allocate(sizes.escape_counts);
  sample_rays_ = allocate(sizes.sample_rays);
  queue_lengths_ = allocate(sizes.queue_lengths);
  for (int parity : {0, 1}) queues_[parity] = allocate(sizes.queues[parity]);
  longest_queue_ = sizes.longest_queue;
  bytes_ = sizes.total();

  if (s.traversal == Traversal::Lanes) {
    const WavefrontCounts counts{frame.camera_hits, escape_counts_, sample_rays_, queue_lengths_,
                                 frame.traversal_totals};
    streams_ = std::make_unique<StreamedBounces>(context, device, program, scene, camera, s, sizes.max_sources, counts);
  } else {
    set_up_bounce_kernels(device, program, scene, camera, s, frame);
  }

  finish_ = cl::Kernel(program, "wavefront_finish");
  cl_uint arg = set_ao_args(finish_, 0, camera, s);
  finish_tile_arg_ = arg;
  finish_.setArg(arg + 2, frame.camera_hits);
  finish_.setArg(arg + 3, escape_counts_);
  finish_.setArg(arg + 4, sample_rays_);
  finish_.setArg(arg + 5, frame.ao);
  finish_.setArg(arg + 6, frame.coverage);
  finish_.setArg(arg + 7, frame.secondary_rays);
  finish_group_ = work_group_size_for(finish_, device, s.work_group_size);
}

void Wavefront::set_up_bounce_kernels(const cl::Device& device, const cl::Program& program, const DeviceScene& scene,
                                      const Camera& camera, const RenderSettings& s, const FrameBuffers& frame) {
  first_bounce_ = cl::Kernel(program, "wavefront_first_bounce");
  cl_uint arg = set_ao_args(first_bounce_, scene.set_args(first_bounce_), camera, s);
  first_bounce_tile_arg_ = arg;
  first_bounce_.setArg(arg + 2, frame.camera_hits);
  first_bounce_.setArg(arg + 3, escape_counts_);
  first_bounce_.setArg(arg + 4, sample_rays_);
  set_buffer_or_null(first_bounce_, arg + 5, queue_of(1));
  first_bounce_.setArg(arg + 6, queue_lengths_);
  set_buffer_or_null(first_bounce_, arg + 7, frame.traversal_totals);

  bounce_ = cl::Kernel(program, "wavefront_bounce");
  arg = set_ao_args(bounce_, scene.set_args(bounce_), camera, s);
  bounce_tile_arg_ = arg;  // then the bounce, its queue, ...
  bounce_.setArg(arg + 3, escape_counts_);
  bounce_.setArg(arg + 4, sample_rays_);
  bounce_.setArg(arg + 6, queue_lengths_);  // ... and the queue it fills
  set_buffer_or_null(bounce_, arg + 7, frame.traversal_totals);

  first_bounce_group_ = work_group_size_for(first_bounce_, device, s.work_group_size);
  bounce_group_ = work_group_size_for(bounce_, device, s.work_group_size);
}

void Wavefront::start_tile(cl::CommandQueue& queue, std::size_t first, std::size_t count) {
  queue.enqueueFillBuffer(queue_lengths_, cl_uint(0), 0, (bounces_ + 1) * sizeof(cl_uint));
  if (streams_) {
    streams_->set_tile(first);
  } else {
    first_bounce_.setArg(first_bounce_tile_arg_, cl_uint(first));
    first_bounce_.setArg(first_bounce_tile_arg_ + 1, cl_uint(count * spp_));
    bounce_.setArg(bounce_tile_arg_, cl_uint(first));
  }
  finish_.setArg(finish_tile_arg_, cl_uint(first));
  finish_.setArg(finish_tile_arg_ + 1, cl_uint(count));
}

void Wavefront::set_bounce(std::size_t bounce) {
  bounce_.setArg(bounce_tile_arg_ + 1, cl_uint(bounce));
  bounce_.setArg(bounce_tile_arg_ + 2, queue_of(bounce - 1));
  set_buffer_or_null(bounce_, bounce_tile_arg_ + 5, queue_of(bounce));
}

void Wavefront::enqueue_tile(cl::CommandQueue& queue, std::size_t first, std::size_t count) {
  start_tile(queue, first, count);
  if (streams_)
    enqueue_streamed_bounces(queue, count * spp_);
  else
    enqueue_bounces(queue, count * spp_);
  launch(queue, finish_, count, finish_group_);
}

void Wavefront::enqueue_bounces(cl::CommandQueue& queue, std::size_t tile_samples) {
  launch(queue, first_bounce_, tile_samples, first_bounce_group_);
  for (std::size_t bounce = 2; bounce <= bounces_; ++bounce) {
    set_bounce(bounce);
    launch(queue, bounce_, queue_length(queue, bounce - 1), bounce_group_);
  }
}

void Wavefront::enqueue_streamed_bounces(cl::CommandQueue& queue, std::size_t tile_samples) {
  streams_->enqueue_bounce(queue, 1, tile_samples, cl::Buffer(), queue_of(1));
  for (std::size_t bounce = 2; bounce <= bounces_; ++bounce)
    streams_->enqueue_bounce(queue, bounce, queue_length(queue, bounce - 1), queue_of(bounce - 1), queue_of(bounce));
}

void Wavefront::enqueue_empty_tiles(cl::CommandQueue& queue, std::size_t tile_pixels) {
  start_tile(queue, 0, 0);
  if (streams_) {
    streams_->enqueue_empty(queue);
  } else {
    launch_empty(queue, first_bounce_, tile_pixels * spp_, first_bounce_group_);
    if (bounces_ > 1) {  // with one bounce the bounce kernel never runs
      set_bounce(2);
      launch_empty(queue, bounce_, longest_queue_, bounce_group_);
    }
  }
  launch_empty(queue, finish_, tile_pixels, finish_group_);
}

std::size_t Wavefront::queue_length(cl::CommandQueue& queue, std::size_t bounce) const {
  cl_uint length = 0;
  queue.enqueueReadBuffer(queue_lengths_, CL_TRUE, bounce * sizeof(cl_uint), sizeof length, &length);
  return length;
}

std::string Wavefront::launch_signature() const {
  const std::string finish = " " + std::to_string(finish_group_);
  if (streams_) return "wavefront " + streams_->launch_signature() + finish;
  // With one bounce the bounce kernel is never launched, so never compiled.
  const std::size_t bounce_group = bounces_ > 1 ? bounce_group_ : 0;
  return "wavefront " + std::to_string(first_bounce_group_) + " " + std::to_string(bounce_group) + finish;
}

}  // namespace mbao
