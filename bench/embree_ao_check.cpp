// The Embree baseline traces mbao's workload: same image, same ray count (to
// within the few rays that float differences in hit points send elsewhere),
// for both estimators and both of Embree's forms. Run by CTest.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "embree_ao.h"
#include "opencl/devices.h"
#include "render/renderer.h"
#include "scene/cornell_box.h"

namespace {

// The Cornell box with its back wall (triangles 6 and 7) cut into a 2 x 2 checkerboard.
std::shared_ptr<mbao::Scene> cornell_with_checkered_back_wall() {
  const auto cornell = mbao::cornell_box();
  mbao::AlphaMasks masks;
  masks.textures.push_back(MaskTexture{0, 2, 2, MBAO_WRAP_REPEAT | (MBAO_WRAP_REPEAT << 2), 1.0f, 0.5f, {0, 0}});
  masks.texels = {255, 0, 0, 255};
  // The wall's quad (549.6,0) (0,0) (0,548.8) (556,548.8) at z = 559.2, split along v0-v2.
  masks.triangles.push_back(MaskedTriangle{{0, 0, 8, 0, 8, 8}, 0, 0});
  masks.triangles.push_back(MaskedTriangle{{0, 0, 8, 8, 0, 8}, 0, 0});
  masks.triangle_mask.assign(cornell->mesh().triangles.size(), MBAO_NOT_MASKED);
  masks.triangle_mask[6] = 0;
  masks.triangle_mask[7] = 1;
  return std::make_shared<mbao::Scene>(cornell->mesh(), "checkered cornell", cornell->camera(),
                                       std::vector<std::string>{}, std::move(masks));
}

}  // namespace

int main() {
  mbao::Renderer& renderer = mbao::Renderer::for_device(mbao::default_device());
  int failures = 0;
  for (const auto& scene : {mbao::cornell_box(), cornell_with_checkered_back_wall()}) {
    const bench::EmbreeAo embree(scene, 2);
    for (const mbao::Estimator estimator : {mbao::Estimator::Branching, mbao::Estimator::Path}) {
      mbao::RenderSettings s;
      s.width = 48;
      s.height = 40;
      s.bounces = 2;
      s.samples = 3;
      s.spp = 2;
      s.rho = 0.7f;
      s.estimator = estimator;
      const mbao::RenderResult reference = renderer.render(scene, *scene->camera(), s);
      for (const auto mode : {bench::EmbreeAo::Mode::SingleRays, bench::EmbreeAo::Mode::Packets16}) {
        const bench::EmbreeFrame frame = embree.render(*scene->camera(), s, mode);
        std::size_t differing = 0;
        double difference = 0.0;
        for (std::size_t p = 0; p < frame.ao.size(); ++p) {
          differing += frame.ao[p] != reference.ao[p];
          difference += std::abs(double(frame.ao[p]) - double(reference.ao[p]));
        }
        const double rays = double(reference.stats.rays_secondary);
        const double ray_difference = std::abs(double(frame.rays_secondary) - rays) / rays;
        const bool ok = frame.rays_primary == reference.stats.rays_primary && differing <= frame.ao.size() / 50 &&
                        ray_difference < 0.01;
        std::printf("%s, %s %s: %zu of %zu pixels differ (mean |difference| %.2g), secondary rays %llu vs %llu: %s\n",
                    scene->name().c_str(), mbao::to_string(estimator).c_str(),
                    mode == bench::EmbreeAo::Mode::SingleRays ? "single" : "packets", differing, frame.ao.size(),
                    difference / double(frame.ao.size()), static_cast<unsigned long long>(frame.rays_secondary),
                    static_cast<unsigned long long>(reference.stats.rays_secondary), ok ? "ok" : "FAILED");
        failures += !ok;
      }
    }
  }
  return failures ? 1 : 0;
}
