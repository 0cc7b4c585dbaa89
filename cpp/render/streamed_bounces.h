#pragma once

#include <cstddef>
#include <string>

#include "opencl/opencl.h"
#include "render/device_scene.h"
#include "render/render_settings.h"
#include "scene/camera.h"

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
  // max_sources: the most sources a bounce of a tile has (camera samples or queue entries).
  StreamedBounces(const cl::Context& context, const cl::Device& device, const cl::Program& program,
                  const DeviceScene& scene, const Camera& camera, const RenderSettings& settings,
                  std::size_t max_sources, const WavefrontCounts& counts);

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
  void enqueue_launch(cl::CommandQueue& queue, std::size_t first_source, std::size_t sources, bool any_hit);

  cl::Device device_;
  std::size_t samples_, bounces_;
  bool bounces_on_;  // rho > 0: bounces before the last need closest hits
  std::size_t sources_per_launch_;
  cl::Buffer ray_origins_, ray_directions_, ray_hits_;
  cl::Kernel rays_, trace_, hits_;
  cl_uint rays_bounce_arg_ = 0, trace_count_arg_ = 0, hits_bounce_arg_ = 0;
  std::size_t rays_group_ = 0, trace_group_ = 0, hits_group_ = 0;
  std::size_t bytes_ = 0;
};

}  // namespace mbao
