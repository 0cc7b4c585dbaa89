#pragma once

#include <cstddef>
#include <string>

#include "opencl/opencl.h"
#include "render/ao_kernel_args.h"
#include "render/device_scene.h"
#include "render/render_plan.h"
#include "render/render_settings.h"

namespace mbao {

// The wavefront's buffers that a bounce reads and adds to (see Wavefront).
struct WavefrontCounts {
  cl::Buffer camera_hits, escape_counts, sample_rays, queue_lengths, traversal_totals;
};

// A wavefront bounce as three launches over a stream of rays, for traversal
// "lanes" (render.cl's stream_bounce_rays and stream_bounce_hits, and
// kd_lanes.h's trace_rays_in_lanes): the sources' rays are written out, walked sixteen per
// work item (kernels/kd_lanes.h), and their hits read back into the counts and
// the next queue. A bounce with more sources than the stream holds is cut into
// launches of at most sources_per_launch().
class StreamedBounces {
 public:
  // kernels: the plan's stream_* kernels. max_sources: the most sources a bounce of a tile has
  // (camera samples or queue entries).
  StreamedBounces(const cl::Context& context, const cl::Device& device, const cl::Program& program,
                  const DeviceScene& scene, const AoArgs& ao_args, const RenderSettings& settings,
                  const FrameKernels& kernels, std::size_t max_sources, const WavefrontCounts& counts);

  void set_tile(std::size_t first_position);
  // Bounce `bounce` from `sources` sources: the tile's camera samples for bounce
  // 1, else the entries of `from`; surfaces that bounce on go into `to`.
  void enqueue_bounce(cl::CommandQueue& queue, std::size_t bounce, std::size_t sources, const cl::Buffer& from,
                      const cl::Buffer& to);
  // Each kernel launched over nothing, on the smallest and the largest grid (launch_empty).
  void enqueue_empty(cl::CommandQueue& queue);

  std::size_t bytes() const { return bytes_; }
  static std::size_t device_bytes(const RenderSettings& settings, std::size_t max_sources);
  std::string launch_signature() const;

 private:
  static std::size_t sources_per_launch(const RenderSettings& settings, std::size_t max_sources);
  // Sets the three kernels' arguments for sources [first_source, first_source + sources) of the bounce.
  void set_launch(std::size_t first_source, std::size_t sources, bool any_hit, std::size_t rays_per_item);
  void enqueue_launch(cl::CommandQueue& queue, std::size_t first_source, std::size_t sources, bool any_hit);

  const DeviceScene& scene_;
  const AoArgs ao_args_;
  const WavefrontCounts counts_;
  cl::Device device_;
  std::size_t samples_, bounces_;
  bool bounces_on_;  // rho > 0: bounces before the last need closest hits
  std::size_t sources_per_launch_;
  cl::Buffer ray_origins_, ray_directions_, ray_hits_;
  cl::Kernel rays_, trace_, hits_;
  // The bounce being launched: its tile's first pixel position, its number, the queue its sources are in
  // (none for bounce 1, whose sources are the camera hits) and the queue it fills (none for the last).
  std::size_t first_position_ = 0, bounce_ = 1;
  cl::Buffer from_, to_;
  std::size_t rays_group_ = 0, trace_group_ = 0, hits_group_ = 0;
  std::size_t bytes_ = 0;
};

}  // namespace mbao
