#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "opencl/opencl.h"
#include "render/ao_kernel_args.h"
#include "render/device_scene.h"
#include "render/render_plan.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "render/wavefront.h"
#include "scene/camera.h"

namespace mbao {

// The device side of one render: its buffers and kernels (render.cl's camera
// rays, which write the G-buffer where the frame has one, then the AO
// megakernel or the wavefront), set up for everything but the tile. A tile is
// a range of positions in the order the kernels take the pixels in
// (kernels/mbao/pixel_order.h: blocks of 16 x 16 in Z order).
class Frame {
 public:
  // `program` is the plan's; the frame launches the plan's kernels and writes its G-buffer planes.
  Frame(const cl::Context& context, const cl::Device& device, const cl::Program& program, const DeviceScene& scene,
        const Camera& camera, const RenderSettings& settings, const RenderPlan& plan, std::size_t tile_pixels,
        PrimarySurfaces primaries = PrimarySurfaces::CameraHits);

  // Camera rays, the G-buffer and the AO, as the frame's output asks, for the pixels at positions
  // [first, first + count) of that order, count <= the tile size.
  void enqueue_tile(cl::CommandQueue& queue, std::size_t first, std::size_t count);
  // A frame of given points: AO from `points`, a surface point (t, triangle, b1, b2 bits; triangle ~0u for
  // none) per camera sample of those positions, in the camera hits' order. Copies them before it returns.
  void enqueue_tile(cl::CommandQueue& queue, std::size_t first, std::size_t count, const std::vector<cl_uint4>& points);
  // Launches every kernel of a tile over no pixels, on the smallest grid and on
  // a whole tile's (launch_empty): what a driver builds at a kernel's first
  // launch, it builds here rather than in a tile.
  void enqueue_empty_tiles(cl::CommandQueue& queue);
  // Copies the image, its coverage and the per-pixel secondary ray counts back
  // (non-blocking), and the second moments and the variances into
  // result.ao_second_moment and result.variance where they are sized for them.
  // A G-buffer frame has no ray counts: `secondary_rays` is not written.
  void enqueue_read_back(cl::CommandQueue& queue, RenderResult& result, cl_uint* secondary_rays);
  // The whole frame's images, once its tiles have run: what the screen-space
  // passes read, and where a G-buffer frame's pass writes the image.
  const FrameBuffers& buffers() const { return buffers_; }
  // The frame's traversal counts (programs built with MBAO_COUNT_TRAVERSAL), once it has finished.
  TraversalTotals traversal_totals(cl::CommandQueue& queue) const;

  // Device memory of the frame's own buffers.
  std::size_t bytes() const { return bytes_; }
  // What a frame with these settings, plan and tile size allocates: known before it does.
  static std::size_t device_bytes(const RenderSettings& settings, const RenderPlan& plan, std::size_t tile_pixels,
                                  PrimarySurfaces primaries = PrimarySurfaces::CameraHits);
  // What decides whether the kernels have been launched before: program, AO kernels, work-group sizes
  // and the tile size (the largest grid).
  std::string launch_signature() const;

 private:
  // Bytes of each buffer, 0 where the frame has none: what decides which buffers a frame has.
  struct BufferSizes {
    std::size_t camera_hits, ao, coverage, secondary_rays, ao_second_moment, ao_variance, gbuffer, traversal_totals;
    std::size_t wavefront;  // the Wavefront's own, where the frame has one
    std::size_t total() const {
      return camera_hits + ao + coverage + secondary_rays + ao_second_moment + ao_variance + gbuffer +
             traversal_totals + wavefront;
    }
  };
  static BufferSizes buffer_sizes(const RenderSettings& settings, const RenderPlan& plan, std::size_t tile_pixels,
                                  PrimarySurfaces primaries);
  void set_tile(std::size_t first, std::size_t count);
  void enqueue_ao(cl::CommandQueue& queue, std::size_t first, std::size_t count);
  // The camera kernel's work items for `pixels` pixels.
  std::size_t camera_items(std::size_t pixels) const;

  const DeviceScene& scene_;
  const CameraArgs camera_args_;
  const AoArgs ao_args_;
  const cl_uint2 seed_;
  std::size_t pixels_, tile_pixels_, spp_;
  std::size_t camera_rays_per_item_;
  cl_uint gbuffer_planes_;  // what the camera rays write of the G-buffer (kernels/mbao/gbuffer.h's masks)
  FrameBuffers buffers_;
  cl::Kernel camera_rays_;
  std::size_t camera_group_ = 0;
  // The megakernel, or else the wavefront; neither in G-buffer frames.
  cl::Kernel ao_kernel_;
  std::size_t ao_group_ = 0;
  std::unique_ptr<Wavefront> wavefront_;
  std::size_t bytes_ = 0;
};

}  // namespace mbao
