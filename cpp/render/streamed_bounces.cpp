#include "render/streamed_bounces.h"

#include <algorithm>

#include "opencl/launch.h"
#include "render/ao_kernel_args.h"

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
// the time in six runs (docs/traversal-on-pocl.md).
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
                                 const DeviceScene& scene, const Camera& camera, const RenderSettings& s,
                                 std::size_t max_sources, const WavefrontCounts& counts)
    : device_(device),
      samples_(std::size_t(s.samples)),
      bounces_(std::size_t(s.bounces)),
      bounces_on_(s.rho > 0.0f),
      sources_per_launch_(sources_per_launch(s, max_sources)) {
  const std::size_t capacity = sources_per_launch_ * samples_;
  ray_origins_ = cl::Buffer(context, CL_MEM_READ_WRITE, capacity * sizeof(cl_float4));
  ray_directions_ = cl::Buffer(context, CL_MEM_READ_WRITE, capacity * sizeof(cl_float4));
  ray_hits_ = cl::Buffer(context, CL_MEM_READ_WRITE, capacity * sizeof(cl_uint4));
  bytes_ = device_bytes(s, max_sources);

  rays_ = cl::Kernel(program, "stream_bounce_rays");
  rays_bounce_arg_ = set_ao_args(rays_, scene.set_args(rays_), camera, s) + 1;  // after first_position
  rays_.setArg(rays_bounce_arg_ + 3, counts.camera_hits);
  rays_.setArg(rays_bounce_arg_ + 5, ray_origins_);
  rays_.setArg(rays_bounce_arg_ + 6, ray_directions_);

  trace_ = cl::Kernel(program, "trace_rays_in_lanes");
  const cl_uint arg = scene.set_args(trace_);
  trace_.setArg(arg, ray_origins_);
  trace_.setArg(arg + 1, ray_directions_);
  trace_count_arg_ = arg + 2;  // then any_hit and rays_per_item
  trace_.setArg(arg + 5, ray_hits_);
  set_buffer_or_null(trace_, arg + 6, cl::Buffer());  // no counts per ray, only the frame's totals
  set_buffer_or_null(trace_, arg + 7, counts.traversal_totals);

  hits_ = cl::Kernel(program, "stream_bounce_hits");
  hits_bounce_arg_ = set_ao_args(hits_, 0, camera, s);
  hits_.setArg(hits_bounce_arg_ + 4, ray_directions_);
  hits_.setArg(hits_bounce_arg_ + 5, ray_hits_);
  hits_.setArg(hits_bounce_arg_ + 6, counts.escape_counts);
  hits_.setArg(hits_bounce_arg_ + 7, counts.sample_rays);
  hits_.setArg(hits_bounce_arg_ + 9, counts.queue_lengths);

  rays_group_ = work_group_size_for(rays_, device, s.work_group_size);
  trace_group_ = lanes_work_group(trace_, device, s.work_group_size);
  hits_group_ = work_group_size_for(hits_, device, s.work_group_size);
}

void StreamedBounces::set_tile(std::size_t first_position) {
  rays_.setArg(rays_bounce_arg_ - 1, cl_uint(first_position));
}

void StreamedBounces::enqueue_bounce(cl::CommandQueue& queue, std::size_t bounce, std::size_t sources,
                                     const cl::Buffer& from, const cl::Buffer& to) {
  rays_.setArg(rays_bounce_arg_, cl_uint(bounce));
  set_buffer_or_null(rays_, rays_bounce_arg_ + 4, from);
  hits_.setArg(hits_bounce_arg_, cl_uint(bounce));
  set_buffer_or_null(hits_, hits_bounce_arg_ + 3, from);
  set_buffer_or_null(hits_, hits_bounce_arg_ + 8, to);
  // Only hits that bounce on need to be the closest.
  const bool any_hit = !(bounce < bounces_ && bounces_on_);
  for (std::size_t first = 0; first < sources; first += sources_per_launch_)
    enqueue_launch(queue, first, std::min(sources_per_launch_, sources - first), any_hit);
}

void StreamedBounces::enqueue_launch(cl::CommandQueue& queue, std::size_t first_source, std::size_t sources,
                                     bool any_hit) {
  rays_.setArg(rays_bounce_arg_ + 1, cl_uint(first_source));
  rays_.setArg(rays_bounce_arg_ + 2, cl_uint(sources));
  launch(queue, rays_, sources, rays_group_);

  const std::size_t rays = sources * samples_;
  const std::size_t per_item = rays_per_lane_item(rays, device_, trace_group_);
  trace_.setArg(trace_count_arg_, cl_uint(rays));
  trace_.setArg(trace_count_arg_ + 1, cl_int(any_hit));
  trace_.setArg(trace_count_arg_ + 2, cl_uint(per_item));
  launch(queue, trace_, (rays + per_item - 1) / per_item, trace_group_);

  hits_.setArg(hits_bounce_arg_ + 1, cl_uint(first_source));
  hits_.setArg(hits_bounce_arg_ + 2, cl_uint(sources));
  launch(queue, hits_, sources, hits_group_);
}

void StreamedBounces::enqueue_empty(cl::CommandQueue& queue) {
  rays_.setArg(rays_bounce_arg_, cl_uint(1));
  set_buffer_or_null(rays_, rays_bounce_arg_ + 4, cl::Buffer());
  rays_.setArg(rays_bounce_arg_ + 1, cl_uint(0));
  rays_.setArg(rays_bounce_arg_ + 2, cl_uint(0));
  launch_empty(queue, rays_, sources_per_launch_, rays_group_);
  trace_.setArg(trace_count_arg_, cl_uint(0));
  trace_.setArg(trace_count_arg_ + 1, cl_int(1));
  trace_.setArg(trace_count_arg_ + 2, cl_uint(1));
  const std::size_t smallest_per_item = rays_per_lane_item(0, device_, trace_group_);
  launch_empty(queue, trace_, (sources_per_launch_ * samples_ + smallest_per_item - 1) / smallest_per_item,
               trace_group_);
  hits_.setArg(hits_bounce_arg_, cl_uint(1));
  set_buffer_or_null(hits_, hits_bounce_arg_ + 3, cl::Buffer());
  set_buffer_or_null(hits_, hits_bounce_arg_ + 8, cl::Buffer());
  hits_.setArg(hits_bounce_arg_ + 1, cl_uint(0));
  hits_.setArg(hits_bounce_arg_ + 2, cl_uint(0));
  launch_empty(queue, hits_, sources_per_launch_, hits_group_);
}

std::string StreamedBounces::launch_signature() const {
  return "streams " + std::to_string(rays_group_) + " " + std::to_string(trace_group_) + " " +
         std::to_string(hits_group_) + " " + std::to_string(sources_per_launch_);
}

}  // namespace mbao
