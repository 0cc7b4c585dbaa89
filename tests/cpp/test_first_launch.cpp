// A frame's empty tiles launch each kernel on every kind of grid its tiles
// launch it on, so that what a driver builds at a kernel's first launch is
// built before the frame's time starts (Renderer::run_traced counts it as
// kernel build time). PoCL shows what it builds: a file in its cache
// directory for each kernel, work-group size and kind of grid.
#include <gtest/gtest.h>

#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <unistd.h>

#include "opencl/compute_context.h"
#include "opencl/devices.h"
#include "render/device_scene.h"
#include "render/frame.h"
#include "render/render_plan.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

namespace fs = std::filesystem;

std::set<std::string> files_under(const fs::path& dir) {
  std::set<std::string> files;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file()) files.insert(fs::relative(entry.path(), dir).string());
  return files;
}

std::set<std::string> added(const std::set<std::string>& before, const std::set<std::string>& after) {
  std::set<std::string> new_files;
  for (const std::string& file : after)
    if (!before.count(file)) new_files.insert(file);
  return new_files;
}

// Everything rendered from here on is built afresh: PoCL reads its cache
// directory when it starts, so this runs before the process's first OpenCL call.
fs::path fresh_caches() {
  const fs::path root = fs::temp_directory_path() / ("mbao-first-launch-" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "pocl");
  fs::create_directories(root / "mbao");
  ::setenv("POCL_CACHE_DIR", (root / "pocl").c_str(), 1);
  ::setenv("MBAO_CACHE_DIR", (root / "mbao").c_str(), 1);
  return root;
}

// Tiles of 100000 pixels and a last one of 62144: grids on either side of
// PoCL's 65535 items, the width up to which it builds a kernel of its own.
RenderSettings three_tiles(KernelOrganisation organisation, Traversal traversal) {
  RenderSettings s;
  s.width = s.height = 512;
  s.bounces = 2;
  s.samples = 1;
  s.organisation = organisation;
  s.traversal = traversal;
  return s;
}
constexpr std::size_t kTilePixels = 100000;

TEST(FirstLaunch, EmptyTilesBuildWhatTheFramesTilesLaunch) {
  const fs::path caches = fresh_caches();
  ComputeContext compute(default_device());
  if (compute.device().platform != "Portable Computing Language")
    GTEST_SKIP() << "only PoCL's cache directory shows what a launch builds";
  const std::shared_ptr<const Scene> scene = cornell_box();
  DeviceSceneCache scenes;
  const std::shared_ptr<const DeviceScene> device_scene = scenes.get(compute, scene, false, false);
  // Any build of render.cl shows it; these are the Cornell box's variants on a CPU, with the traversal the
  // frame's settings name (lanes programs have kernels of their own, camera packets included).
  const auto program_for = [&](Traversal traversal) {
    ProgramVariant variant;
    variant.walk = traversal;
    variant.load_both_children = true;
    return compute.programs().get(variant.file(), variant.options()).program;
  };
  const cl::Program programs[] = {program_for(Traversal::Stack), program_for(Traversal::Lanes)};
  if (files_under(caches / "pocl").empty())
    GTEST_SKIP() << "PoCL started before this test set its cache directory: run the test in a process of its "
                    "own, as ctest does";

  // The wavefront with lanes launches other bounce kernels, the walk's on grids that follow the rays' count.
  const std::pair<KernelOrganisation, Traversal> kinds[] = {{KernelOrganisation::Megakernel, Traversal::Stack},
                                                            {KernelOrganisation::Wavefront, Traversal::Stack},
                                                            {KernelOrganisation::Wavefront, Traversal::Lanes}};
  for (const auto& [organisation, traversal] : kinds) {
    SCOPED_TRACE(to_string(organisation) + " " + to_string(traversal));
    const RenderSettings settings = three_tiles(organisation, traversal);
    const std::size_t pixels = std::size_t(settings.width) * std::size_t(settings.height);
    cl::CommandQueue& queue = compute.queue();
    const Camera camera = scene->camera()->relative_to(scene->render_origin());
    const cl::Program& program = programs[traversal == Traversal::Lanes];
    const RenderPlan plan = plan_render(settings, compute.device(), SceneTraits::of(*scene));
    Frame frame(compute.context(), compute.device().device, program, *device_scene, camera, settings, plan,
                kTilePixels);
    const std::set<std::string> before = files_under(caches / "pocl");
    frame.enqueue_empty_tiles(queue);
    queue.finish();
    const std::set<std::string> warmed = files_under(caches / "pocl");
    EXPECT_FALSE(added(before, warmed).empty());  // the kernels were built at their first launch, here
    for (std::size_t first = 0; first < pixels; first += kTilePixels)
      frame.enqueue_tile(queue, first, std::min(kTilePixels, pixels - first));
    queue.finish();
    EXPECT_EQ(added(warmed, files_under(caches / "pocl")), std::set<std::string>{});
  }
  fs::remove_all(caches);
}

}  // namespace
}  // namespace mbao
