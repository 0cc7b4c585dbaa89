#include "render/streamed_bounces.h"

#include <algorithm>

#include "opencl/launch.h"

namespace mbao {
namespace {

// The most rays a stream holds: 96 MiB of rays and hits. A launch of a
// million rays keeps two CPU cores' lanes full; the few launches a larger
// bounce is cut into cost next to nothing beside the walk.
constexpr std::size_t kMaxStreamRays = std::size_t(1) << 21;
constexpr std::size_t kBytesPerRay = 2 * sizeof(cl_float4) + sizeof(cl_uint4);  // origin, direction, hit

// The lanes' walk has few, long work items (up to 512 rays each: launch.h's
// rays_per_lane_item). On a CPU, in groups of 8 rather than 64, the cores
// share the last of them more evenly: Sponza's b = 1 frame took 0.96-1.00 of
// the time in six runs (docs/traversal.md).
constexpr std::size_t kCpuLanesGroup = 8;

std::size_t lanes_work_group(const cl::Kernel& trace, const cl::Device& device, std::size_t requested) {
  const std::size_t group = work_group_size_for(trace, device, requested);
  const bool cpu = (device.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU) != 0;
  return requested || !cpu ? group : std::min(group, kCpuLanesGroup);
}

}  // namespace

std::size_t StreamedBounces::sources_per_launch(const RenderSettings& s, std::size_t max_sources) {
  return std::max<std::size_t>(1, std::min(max_sources, kMaxStreamRays / std::size_t(s.samples)));
}

std::size_t StreamedBounces::device_bytes(const RenderSettings& s, std::size_t max_sources) {
  return sources_per_launch(s, max_sources) * std::size_t(s.samples) * kBytesPerRay;
}

StreamedBounces::StreamedBounces(const cl::Context& context, const cl::Device& device, const cl::Program& program,
                                 const DeviceScene& scene, const AoArgs& ao_args, const RenderSettings& s,
                                 const FrameKernels& kernels, std::size_t max_sources, const WavefrontCounts& counts)
    : scene_(scene),
      ao_args_(ao_args),
      counts_(counts),
      device_(device),
      samples_(std::size_t(s.samples)),
      bounces_(std::size_t(s.bounces)),
      bounces_on_(s.rho > 0.0f),
      sources_per_launch_(sources_per_launch(s, max_sources)) {
  const std::size_t capacity = sources_per_launch_ * samples_;
  ray_origins_ = cl::Buffer(context, CL_MEM_READ_WRITE, capacity * sizeof(cl_float4));
  ray_directions_ = cl::Buffer(context, CL_MEM_READ_WRITE, capacity * sizeof(cl_float4));
  ray_hits_ = cl::Buffer(context, CL_MEM_READ_WRITE, capacity * sizeof(cl_uint4));
  bytes_ = device_bytes(s, max_sources);

  rays_ = cl::Kernel(program, kernels.stream_rays.c_str());
  trace_ = cl::Kernel(program, kernels.stream_trace.c_str());
  hits_ = cl::Kernel(program, kernels.stream_hits.c_str());
  rays_group_ = work_group_size_for(rays_, device, s.work_group_size);
  trace_group_ = lanes_work_group(trace_, device, s.work_group_size);
  hits_group_ = work_group_size_for(hits_, device, s.work_group_size);
}

void StreamedBounces::set_tile(std::size_t first_position) { first_position_ = first_position; }

void StreamedBounces::enqueue_bounce(cl::CommandQueue& queue, std::size_t bounce, std::size_t sources,
                                     const cl::Buffer& from, const cl::Buffer& to) {
  bounce_ = bounce;
  from_ = from;
  to_ = to;
  // Only hits that bounce on need to be the closest.
  const bool any_hit = !(bounce < bounces_ && bounces_on_);
  for (std::size_t first = 0; first < sources; first += sources_per_launch_)
    enqueue_launch(queue, first, std::min(sources_per_launch_, sources - first), any_hit);
}

void StreamedBounces::set_launch(std::size_t first_source, std::size_t sources, bool any_hit,
                                 std::size_t rays_per_item) {
  set_kernel_args(rays_, scene_, ao_args_, cl_uint(first_position_), cl_uint(bounce_), cl_uint(first_source),
                  cl_uint(sources), counts_.camera_hits, from_, ray_origins_, ray_directions_);
  // No counts per ray, only the frame's totals.
  set_kernel_args(trace_, scene_, ray_origins_, ray_directions_, cl_uint(sources * samples_), cl_int(any_hit),
                  cl_uint(rays_per_item), ray_hits_, cl::Buffer(), counts_.traversal_totals);
  set_kernel_args(hits_, ao_args_, cl_uint(bounce_), cl_uint(first_source), cl_uint(sources), from_, ray_directions_,
                  ray_hits_, counts_.escape_counts, counts_.sample_rays, to_, counts_.queue_lengths);
}

void StreamedBounces::enqueue_launch(cl::CommandQueue& queue, std::size_t first_source, std::size_t sources,
                                     bool any_hit) {
  const std::size_t rays = sources * samples_;
  const std::size_t per_item = rays_per_lane_item(rays, device_, trace_group_);
  set_launch(first_source, sources, any_hit, per_item);
  launch(queue, rays_, sources, rays_group_);
  launch(queue, trace_, (rays + per_item - 1) / per_item, trace_group_);
  launch(queue, hits_, sources, hits_group_);
}

void StreamedBounces::enqueue_empty(cl::CommandQueue& queue) {
  bounce_ = 1;
  from_ = to_ = cl::Buffer();
  set_launch(0, 0, true, 1);
  launch_empty(queue, rays_, sources_per_launch_, rays_group_);
  const std::size_t smallest_per_item = rays_per_lane_item(0, device_, trace_group_);
  launch_empty(queue, trace_, (sources_per_launch_ * samples_ + smallest_per_item - 1) / smallest_per_item,
               trace_group_);
  launch_empty(queue, hits_, sources_per_launch_, hits_group_);
}

std::string StreamedBounces::launch_signature() const {
  return "streams " + std::to_string(rays_group_) + " " + std::to_string(trace_group_) + " " +
         std::to_string(hits_group_) + " " + std::to_string(sources_per_launch_);
}

}  // namespace mbao
