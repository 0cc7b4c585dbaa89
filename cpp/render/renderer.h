#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "accel/kd_tree.h"
#include "opencl/compute_context.h"
#include "render/device_scene.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace mbao {

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

// What `requested` means on `device`, for rays in a scene whose tree is
// `tree`: Auto is, on CPUs, lanes for trees at least kMinLanesDepth deep
// (Sponza 0.81-0.88 and Sibenik 0.81-0.89 of the full stack's frame on PoCL,
// the Stanford bunny, whose rays mostly escape, 1.02-1.08) and the full stack
// otherwise (the Cornell box, 6 deep: lanes 1.08-1.18; the full stack has the
// fewest nodes per ray and on PoCL the fastest frames of the walks of one ray,
// mbao_bench's "traversals" section); on other devices the short stack, Horn et
// al.'s choice for GPUs (on an H100 the two stacks tie and restart and
// push-down are slower: bench/results/nvidia-h100.json; the short stack keeps
// a work item's state small, where lanes keep sixteen stacks).
Traversal traversal_for(Traversal requested, const DeviceInfo& device, const KdTreeStats& tree);
constexpr int kMinLanesDepth = 16;
// The same for a render, where lanes run in the wavefront only: Auto takes them
// only where the wavefront can run the settings and the megakernel was not asked for.
Traversal traversal_for(const RenderSettings& settings, const DeviceInfo& device, const KdTreeStats& tree);

// The organisation `settings` run with on `device`: Auto is the wavefront on GPUs
// wherever it can run the settings (on an H100 at b = 2, 0.75-0.91 of the megakernel's
// frame where many rays escape and a tie on closed scenes; a tie at b = 1;
// bench/results/nvidia-h100.json) and the megakernel
// otherwise (on PoCL they tie and the wavefront needs memory for its queues;
// README "Megakernel against wavefront"), except that traversal lanes runs in the wavefront.
KernelOrganisation organisation_for(const RenderSettings& settings, const DeviceInfo& device);

// Whether the rays leaving one surface point share its path down the tree
// (settings.origin_paths where set): on CPUs, for trees at least
// kMinOriginPathDepth deep. There a walk's first descent, over nodes fetched
// one after another, costs enough that taking them from the path pays (Sponza:
// 0.96 / 0.93 of the frame at b = 1 / 2 on PoCL); on the Cornell box's tree, 6
// deep, the path's setup costs more than it saves (1.04). On an H100 they cost
// up to 6% of the frame at b = 2 (bench/results/nvidia-h100-origin-paths-alternating/):
// there a path per bounce level, 264 bytes, sits in each work item's private memory.
bool origin_paths_for(const RenderSettings& settings, const DeviceInfo& device, const KdTreeStats& tree);
constexpr int kMinOriginPathDepth = 16;

// Renders and traces on one OpenCL device, keeping its built programs and the
// scenes uploaded to it. One per device for the life of the process (for_device);
// calls are serialized.
class Renderer {
 public:
  explicit Renderer(const DeviceInfo& device) : compute_(device) {}
  static Renderer& for_device(const DeviceInfo& device);

  const DeviceInfo& device() const { return compute_.device(); }

  // between_tiles(done, total), if given, runs after each tile has finished,
  // with nothing left in flight: it may report progress, or throw to stop the
  // render, leaving the renderer ready for the next one.
  using TileCallback = std::function<void(std::size_t done, std::size_t total)>;
  RenderResult render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                      const RenderSettings& settings, const TileCallback& between_tiles = {});

  // Traces rays given as origins and direction + t_max in .w; closest hits, or
  // with any_hit the first hit found.
  TraceResult trace(const std::shared_ptr<const Scene>& scene, const std::vector<cl_float4>& origins,
                    const std::vector<cl_float4>& directions, bool any_hit, Traversal traversal,
                    bool count_traversal = false);

 private:
  // The two kinds of frame, given the scene on the device and the camera in its frame.
  void run_traced(const DeviceScene& scene, const cl::Program& program, const Camera& camera,
                  const RenderSettings& requested, const TileCallback& between_tiles, RenderResult& result);
  void run_hbao(const DeviceScene& scene, const cl::Program& program, const Camera& camera,
                const RenderSettings& settings, RenderResult& result);

  ComputeContext compute_;
  DeviceSceneCache scenes_;
  std::set<std::string> launched_;  // Frame::launch_signature() of every frame so far
  std::mutex mutex_;
};

}  // namespace mbao
