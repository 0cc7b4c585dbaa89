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

// Each bounce as a stream of rays (StreamedBounces), as the plan says for lanes.
bool streamed(const FrameKernels& kernels) { return kernels.ao == AoLaunches::StreamedWavefront; }

}  // namespace

Wavefront::BufferSizes Wavefront::buffer_sizes(const RenderSettings& s, const FrameKernels& kernels,
                                               std::size_t tile_pixels) {
  const std::size_t tile_samples = tile_pixels * std::size_t(s.spp);
  BufferSizes sizes;
  // Per camera sample, or per direction at its primary hit (SPEC 7.1), and bounce.
  const std::size_t counted = s.direction_moments() ? std::size_t(s.samples) : 1;
  sizes.escape_counts = tile_samples * counted * std::size_t(s.bounces) * sizeof(cl_uint);
  sizes.sample_rays = tile_samples * sizeof(cl_uint);
  sizes.queue_lengths = (std::size_t(s.bounces) + 1) * sizeof(cl_uint);
  for (std::int64_t parity : {0, 1})
    sizes.queues[parity] = tile_samples * queue_entries_per_camera_sample(s, parity) * sizeof(QueuedSurface);
  sizes.longest_queue = std::max(sizes.queues[0], sizes.queues[1]) / sizeof(QueuedSurface);
  sizes.max_sources = std::max(tile_samples, sizes.longest_queue);
  sizes.streams = streamed(kernels) ? StreamedBounces::device_bytes(s, sizes.max_sources) : 0;
  return sizes;
}

std::size_t Wavefront::device_bytes(const RenderSettings& s, const FrameKernels& kernels, std::size_t tile_pixels) {
  return buffer_sizes(s, kernels, tile_pixels).total();
}

Wavefront::Wavefront(const cl::Context& context, const cl::Device& device, const cl::Program& program,
                     const DeviceScene& scene, const AoArgs& ao_args, const RenderSettings& s,
                     const FrameKernels& kernels, std::size_t tile_pixels, const FrameBuffers& frame)
    : scene_(scene), ao_args_(ao_args), frame_(frame), spp_(std::size_t(s.spp)), bounces_(std::size_t(s.bounces)) {
  const BufferSizes sizes = buffer_sizes(s, kernels, tile_pixels);
  const auto allocate = [&](std::size_t bytes) {
    return bytes ? cl::Buffer(context, CL_MEM_READ_WRITE, bytes) : cl::Buffer();
  };
  escape_counts_ = allocate(sizes.escape_counts);
  sample_rays_ = allocate(sizes.sample_rays);
  queue_lengths_ = allocate(sizes.queue_lengths);
  for (int parity : {0, 1}) queues_[parity] = allocate(sizes.queues[parity]);
  longest_queue_ = sizes.longest_queue;
  bytes_ = sizes.total();

  if (streamed(kernels)) {
    const WavefrontCounts counts{frame.camera_hits, escape_counts_, sample_rays_, queue_lengths_,
                                 frame.traversal_totals};
    streams_ = std::make_unique<StreamedBounces>(context, device, program, scene, ao_args, s, kernels,
                                                 sizes.max_sources, counts);
  } else {
    first_bounce_ = cl::Kernel(program, kernels.first_bounce.c_str());
    bounce_ = cl::Kernel(program, kernels.bounce.c_str());
    first_bounce_group_ = work_group_size_for(first_bounce_, device, s.work_group_size);
    bounce_group_ = work_group_size_for(bounce_, device, s.work_group_size);
  }
  finish_ = cl::Kernel(program, kernels.finish.c_str());
  finish_group_ = work_group_size_for(finish_, device, s.work_group_size);
}

void Wavefront::start_tile(cl::CommandQueue& queue, std::size_t first, std::size_t count) {
  zero_words(queue, queue_lengths_, bounces_ + 1);
  first_position_ = first;
  if (streams_) {
    streams_->set_tile(first);
  } else {
    set_kernel_args(first_bounce_, scene_, ao_args_, cl_uint(first), cl_uint(count * spp_), frame_.camera_hits,
                    escape_counts_, sample_rays_, queue_of(1), queue_lengths_, frame_.traversal_totals);
  }
  set_kernel_args(finish_, ao_args_, cl_uint(first), cl_uint(count), frame_.camera_hits, escape_counts_, sample_rays_,
                  frame_.ao, frame_.ao_second_moment, frame_.ao_variance, frame_.coverage, frame_.secondary_rays);
}

void Wavefront::set_bounce(std::size_t bounce) {
  set_kernel_args(bounce_, scene_, ao_args_, cl_uint(first_position_), cl_uint(bounce), queue_of(bounce - 1),
                  escape_counts_, sample_rays_, queue_of(bounce), queue_lengths_, frame_.traversal_totals);
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
  read_buffer(queue, queue_lengths_, true, bounce * sizeof(cl_uint), sizeof length, &length);
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
