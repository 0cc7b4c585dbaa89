// The AO workload of mbao's render, traced by Embree 3 on the CPU: the same
// camera rays, the same random numbers (kernels/mbao/philox.h), directions,
// ray origins, estimators and alpha masks, so that the rays are the same and
// only the tracer differs. For the benchmark only.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "render/render_settings.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace bench {

struct EmbreeFrame {
  double frame_ms = 0.0;
  std::uint64_t rays_primary = 0, rays_secondary = 0;
  std::vector<float> ao;  // row-major, as mbao's
};

class EmbreeAo {
 public:
  // Single rays (rtcIntersect1 / rtcOccluded1), or 16-wide packets of the rays
  // of one bounce of 16 camera samples (rtcIntersect16 / rtcOccluded16).
  enum class Mode { SingleRays, Packets16 };

  // A high-quality BVH; `robust` adds RTC_SCENE_FLAG_ROBUST (a structure for
  // robust traversal, no optimisations that lose accuracy: mbao's own
  // guarantee). Embree builds it in a fraction of the time of the other on
  // large scenes, so a build comparison names which it is.
  EmbreeAo(std::shared_ptr<const mbao::Scene> scene, unsigned threads, bool robust = false);
  ~EmbreeAo();
  EmbreeAo(const EmbreeAo&) = delete;
  EmbreeAo& operator=(const EmbreeAo&) = delete;

  double build_ms() const { return build_ms_; }
  EmbreeFrame render(const mbao::Camera& camera, const mbao::RenderSettings& settings, Mode mode) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double build_ms_ = 0.0;
};

}  // namespace bench
