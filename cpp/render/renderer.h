#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "accel/kd_tree.h"
#include "opencl/compute_context.h"
#include "render/ao_kernel_args.h"
#include "render/device_scene.h"
#include "render/render_plan.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "render/temporal_history.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace mbao {

class Frame;

// One traced ray: t is +inf and triangle ~0u where it hit nothing.
struct RayHit {
  float t;
  std::uint32_t triangle;
  float b1, b2;  // barycentric weights of the triangle's second and third corner
};

struct TraceResult {
  std::vector<RayHit> hits;
  std::vector<cl_uint4> counts;  // per ray: nodes, leaves, triangle tests, restarts (when counted)
};

// The AO radius of a render with `settings`, by SPEC 1's rule: the radius given
// wins; else the camera's suggestion; else inf, and for HBAO, which needs a
// finite one, a quarter of the scene's diagonal. `source` says which: "settings",
// "camera", "scene" or "none".
struct AoRadius {
  float value;
  std::string source;
};
AoRadius radius_for(const RenderSettings& settings, const Camera& camera, const Scene& scene);

// Renders and traces on one OpenCL device, keeping its built programs and the
// scenes uploaded to it. One per device for the life of the process (for_device);
// calls are serialized.
class Renderer {
 public:
  // With QueueTiming::On, a CommandTimes on queue() times the kernels and read-backs of its renders.
  explicit Renderer(const DeviceInfo& device, QueueTiming timing = QueueTiming::Off) : compute_(device, timing) {}
  static Renderer& for_device(const DeviceInfo& device);

  const DeviceInfo& device() const { return compute_.device(); }
  const cl::CommandQueue& queue() { return compute_.queue(); }

  // between_tiles(done, total), if given, runs after each tile has finished,
  // with nothing left in flight: it may report progress, or throw to stop the
  // render, leaving the renderer ready for the next one.
  using TileCallback = std::function<void(std::size_t done, std::size_t total)>;
  // settings.max_distance, where unset, follows SPEC 1's rule (stats.max_distance_source says which part).
  // With `history`, the frame is one of a sequence that accumulates (SPEC 7.4): blended with
  // history's frames before any spatial filter, it becomes their history; result.history_length
  // holds each pixel's.
  RenderResult render(const std::shared_ptr<const Scene>& scene, const Camera& camera, const RenderSettings& settings,
                      const TileCallback& between_tiles = {}, TemporalHistory* history = nullptr);

  // A bake's estimates (SPEC 6): settings.width x height pixels, each the mean (result.ao) and the mean
  // square (result.ao_second_moment) of settings.spp estimates, one path each, from the surface points
  // that points_of_tile gives for a tile (Frame::enqueue_tile's `points`) as the tiles go. The radius is
  // settings.max_distance, else inf: a bake has no camera to suggest one.
  using TilePoints = std::function<void(std::size_t first_position, std::size_t count, std::vector<cl_uint4>& points)>;
  // Only the positions [first_position, end_position) of the image (mbao/pixel_order.h) are traced
  // where a range is given: each pixel's estimates are keyed by the pixel, so the pixels of any
  // split of the positions are those of the whole image, bit for bit.
  RenderResult bake(const std::shared_ptr<const Scene>& scene, const RenderSettings& settings,
                    const TilePoints& points_of_tile, const TileCallback& between_tiles = {},
                    std::size_t first_position = 0, std::size_t end_position = std::numeric_limits<std::size_t>::max());

  // The G-buffer (SPEC 7.2) of settings.width x height pixels, as HBAO's frames
  // make it, in result.gbuffer: GBUFFER_PLANES planes of a float per pixel
  // (kernels/mbao/gbuffer.h), positions in the scene's device frame.
  // result.ao and result.coverage are empty: the triangle plane says which pixels a camera ray hit.
  RenderResult gbuffer(const std::shared_ptr<const Scene>& scene, const Camera& camera, const RenderSettings& settings);

  // Traces rays given as origins and direction + t_max in .w; closest hits, or
  // with any_hit the first hit found.
  TraceResult trace(const std::shared_ptr<const Scene>& scene, const std::vector<cl_float4>& origins,
                    const std::vector<cl_float4>& directions, bool any_hit, Traversal traversal,
                    bool traversal_stats = false);

 private:
  // A bake's points, for the positions it traces.
  struct BakeTiles {
    const TilePoints& points;
    std::size_t first_position, end_position;
  };
  // render, bake and gbuffer: a bake's points, where given, stand for the camera rays; a G-buffer
  // alone runs no pass after it.
  RenderResult run(const std::shared_ptr<const Scene>& scene, const Camera& camera, const RenderSettings& requested,
                   const TileCallback& between_tiles, const BakeTiles* bake_tiles, TemporalHistory* history = nullptr,
                   RenderProduct product = RenderProduct::Image);
  // The kinds of frame, given the scene on the device, the camera in its frame and the plan
  // (whose program `program` is).
  void run_traced(const DeviceScene& scene, const cl::Program& program, const Camera& camera,
                  const RenderSettings& settings, const RenderPlan& plan, const TileCallback& between_tiles,
                  const BakeTiles* bake_tiles, TemporalHistory* history, RenderResult& result);
  // The temporal accumulation and the spatial filter, in that order, where the settings ask for them.
  void run_screen_space_passes(Frame& frame, const Camera& camera, const RenderSettings& settings,
                               TemporalHistory* history, RenderResult& result);
  // A program that walks no tree (hbao.cl, denoise.cl, temporal.cl), its build time added to stats.
  cl::Program screen_space_program(Program program, RenderStats& stats);
  // A G-buffer frame (the camera rays and their G-buffer), then HBAO's pass where the plan's output is
  // the planes it reads, else the whole G-buffer read back into result.gbuffer.
  void run_gbuffer(const DeviceScene& scene, const cl::Program& program, const Camera& camera,
                   const RenderSettings& settings, const RenderPlan& plan, RenderResult& result);

  ComputeContext compute_;
  DeviceSceneCache scenes_;
  std::set<std::string> launched_;  // Frame::launch_signature() of every frame so far
  std::mutex mutex_;
};

}  // namespace mbao
