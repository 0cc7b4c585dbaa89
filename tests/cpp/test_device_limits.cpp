// What the renderer knows before it asks the device for anything, and what a
// failing device request tells the caller.
#include <gtest/gtest.h>

#include "core/error.h"
#include "opencl/compute_context.h"
#include "opencl/devices.h"
#include "render/frame.h"
#include "render/renderer.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

RenderSettings small(KernelOrganisation organisation, std::int64_t bounces, bool traversal_stats) {
  RenderSettings settings;
  settings.width = 24;
  settings.height = 16;
  settings.bounces = bounces;
  settings.tile_pixels = 64;
  settings.organisation = organisation;
  settings.traversal_stats = traversal_stats;
  return settings;
}

// The scene's part of memory_bytes is the same in every render of one scene,
// so differences between renders are the frames' alone.
TEST(FrameMemory, IsKnownExactlyBeforeAllocation) {
  const std::shared_ptr<const Scene> scene = cornell_box();
  Renderer& renderer = Renderer::for_device(default_device());
  const Camera camera = *scene->camera();
  const auto frame_bytes = [&](const RenderSettings& s) {
    return Frame::device_bytes(s, plan_render(s, renderer.device(), SceneTraits::of(*scene)), 64);
  };
  const RenderSettings base = small(KernelOrganisation::Megakernel, 1, false);
  const std::size_t base_bytes = renderer.render(scene, camera, base).stats.memory_bytes;
  for (const RenderSettings& settings :
       {small(KernelOrganisation::Megakernel, 3, true), small(KernelOrganisation::Wavefront, 2, false),
        small(KernelOrganisation::Wavefront, 4, true)}) {
    const std::size_t bytes = renderer.render(scene, camera, settings).stats.memory_bytes;
    EXPECT_EQ(bytes - base_bytes, frame_bytes(settings) - frame_bytes(base));
  }
}

TEST(KernelBuild, FailureCarriesTheCompilersLog) {
  ComputeContext compute(default_device());
  try {
    compute.programs().get("render.cl", "-Dinline=@");  // every kernel header uses `inline`
    FAIL() << "the build succeeded";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("building kernels/render.cl with options \"-Dinline=@\" failed"), std::string::npos)
        << message;
    EXPECT_NE(message.find("error"), std::string::npos) << "no compiler log in: " << message;
  }
}

}  // namespace
}  // namespace mbao
