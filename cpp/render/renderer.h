#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "accel/kd_tree.h"
#include "opencl/compute_context.h"
#include "render/device_scene.h"
#include "render/render_settings.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace mbao {

struct RenderStats {
  double build_ms = 0.0;         // kd-tree build (done once per scene; see tree_reused)
  bool tree_reused = false;      // the tree existed before this render
  double kernel_build_ms = 0.0;  // getting the program (and, on first launch, its kernels) ready
  std::string kernel_cache;      // where the program came from: "memory", "disk" or "compiled"
  std::string kernel_options;    // what it was built for (SPEC features compiled in or out)
  double upload_ms = 0.0;        // scene upload in this render; 0 when the scene was on the device
  double frame_ms = 0.0;         // camera rays, AO and read-back of the image
  std::uint64_t rays_primary = 0;
  std::uint64_t rays_secondary = 0;
  std::size_t memory_bytes = 0;  // device memory: scene, tile buffers and image
  std::size_t tiles = 0;
  std::string device;
  KdTreeStats tree;
};

struct RenderResult {
  int width = 0, height = 0;
  std::vector<float> ao;              // row-major, row 0 at the top; 1 = open
  std::vector<std::uint8_t> mask;     // 1 where any camera sample hit geometry
  RenderStats stats;
};

// One traced ray: t is +inf and triangle ~0u where it hit nothing.
struct RayHit {
  float t;
  std::uint32_t triangle;
  float b1, b2;  // barycentric weights of the triangle's second and third corner
};

// Renders and traces on one OpenCL device, keeping its built programs and the
// scenes uploaded to it. One per device for the life of the process (for_device);
// calls are serialized.
class Renderer {
 public:
  explicit Renderer(const DeviceInfo& device) : compute_(device) {}
  static Renderer& for_device(const DeviceInfo& device);

  const DeviceInfo& device() const { return compute_.device(); }

  RenderResult render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                      const RenderSettings& settings);

  // Traces rays given as origins and direction + t_max in .w; closest hits, or
  // with any_hit the first hit found.
  std::vector<RayHit> trace(const std::shared_ptr<const Scene>& scene, const std::vector<cl_float4>& origins,
                            const std::vector<cl_float4>& directions, bool any_hit, Traversal traversal);

 private:
  ComputeContext compute_;
  DeviceSceneCache scenes_;
  std::set<std::string> launched_;  // Frame::launch_signature() of every frame so far
  std::mutex mutex_;
};

}  // namespace mbao
