// The wavefront organisation against the megakernel: the same image bit for
// bit, the same rays and the same traversal work, on the device the renderer
// picks by default, whether its bounces walk one ray per work item (the full
// stack) or sixteen (lanes, kernels/kd_lanes.h).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "opencl/devices.h"
#include "render/renderer.h"
#include "scene/cornell_box.h"
#include "scene/gltf_loader.h"

namespace mbao {
namespace {

// The shared scenes beside the checkout, where the Python tests look for them too.
std::filesystem::path shared_scenes() {
  if (const char* dir = std::getenv("MBAO_SHARED_SCENES")) return dir;
  return std::filesystem::path(MBAO_SOURCE_DIR).parent_path() / "shared" / "scenes";
}

RenderResult render(const std::shared_ptr<const Scene>& scene, const Camera& camera, RenderSettings settings,
                    KernelOrganisation organisation, Traversal traversal = Traversal::Stack) {
  settings.organisation = organisation;
  settings.traversal = traversal;
  return Renderer::for_device(default_device()).render(scene, camera, settings);
}

constexpr Traversal kWavefrontWalks[] = {Traversal::Stack, Traversal::Lanes};

// Counts pixels whose float bits differ: the wavefront promises the
// megakernel's float operations, not just close values.
std::size_t differing_pixels(const std::vector<float>& a, const std::vector<float>& b) {
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differing += std::memcmp(&a[i], &b[i], sizeof(float)) != 0;
  return differing;
}

void expect_same_render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                        const RenderSettings& settings) {
  const RenderResult mega = render(scene, camera, settings, KernelOrganisation::Megakernel);
  for (const Traversal walk : kWavefrontWalks) {
    SCOPED_TRACE(scene->name() + ", b=" + std::to_string(settings.bounces) + ", " + to_string(walk));
    const RenderResult wave = render(scene, camera, settings, KernelOrganisation::Wavefront, walk);
    EXPECT_EQ(wave.stats.traversal_mode, to_string(walk));
    ASSERT_EQ(mega.ao.size(), wave.ao.size());
    EXPECT_EQ(differing_pixels(mega.ao, wave.ao), 0u);
    EXPECT_EQ(mega.coverage, wave.coverage);
    EXPECT_EQ(mega.stats.rays_secondary, wave.stats.rays_secondary);
    // Not a vacuous agreement: rays were traced and some light was blocked.
    EXPECT_GT(wave.stats.rays_secondary, 0u);
    double sum = 0.0;
    for (float v : wave.ao) sum += v;
    EXPECT_LT(sum, double(wave.ao.size()));
  }
}

RenderSettings small(std::int64_t bounces) {
  RenderSettings s;
  s.width = s.height = 64;
  s.bounces = bounces;
  return s;
}

TEST(Wavefront, StatsNameTheOrganisationThatRan) {
  const auto box = cornell_box();
  RenderSettings s = small(2);
  s.width = s.height = 8;
  Renderer& renderer = Renderer::for_device(default_device());
  EXPECT_EQ(renderer.render(box, *box->camera(), s).stats.organisation,
            to_string(plan_render(s, renderer.device(), SceneTraits::of(*box)).organisation));
  for (KernelOrganisation named : {KernelOrganisation::Megakernel, KernelOrganisation::Wavefront})
    EXPECT_EQ(render(box, *box->camera(), s, named).stats.organisation, to_string(named));
}

TEST(Wavefront, CornellBoxIsTheMegakernelsImageBitForBit) {
  const auto cornell = cornell_box();
  for (std::int64_t b : {1, 2, 3}) expect_same_render(cornell, *cornell->camera(), small(b));
}

// Several tiles (the last one short), jittered camera samples, a distance
// limit, rho < 1 and small work groups: none of them may change the image.
TEST(Wavefront, TilesAndTheOtherSettingsKeepTheImage) {
  const auto cornell = cornell_box();
  RenderSettings s = small(3);
  s.tile_pixels = 1000;
  s.spp = 2;
  s.rho = 0.7f;
  s.max_distance = 300.0f;
  s.work_group_size = 16;
  s.seed = 12345;
  expect_same_render(cornell, *cornell->camera(), s);
}

// Sponza has alpha masks and shading normals, and its camera a distance limit.
TEST(Wavefront, SponzaIsTheMegakernelsImageBitForBit) {
  const std::filesystem::path folder = shared_scenes() / "sponza";
  if (!std::filesystem::exists(folder / "scene.glb")) GTEST_SKIP() << "no shared scene at " << folder;
  const auto sponza = load_gltf((folder / "scene.glb").string());
  const Camera camera = Camera::load((folder / "camera.json").string());
  for (std::int64_t b : {1, 2, 3}) {
    RenderSettings s = small(b);
    s.width = s.height = 48;
    s.max_distance = *camera.max_distance;
    expect_same_render(sponza, camera, s);
  }
}

// With rho = 0 nothing bounces on, but the queues are sized for r^5 + r^4
// surfaces per pixel: a whole-frame tile would pass kMaxWavefrontQueueEntries.
TEST(Wavefront, QueuesStayBoundedWhateverTileIsAskedFor) {
  const auto cornell = cornell_box();
  RenderSettings s = small(6);
  s.rho = 0.0f;
  s.tile_pixels = std::size_t(s.width * s.height);
  const std::uint64_t queue_per_pixel = s.max_queue_entries_per_camera_sample();
  ASSERT_GT(s.tile_pixels * queue_per_pixel, kMaxWavefrontQueueEntries);
  const RenderResult wave = render(cornell, *cornell->camera(), s, KernelOrganisation::Wavefront);
  const std::size_t tile = std::size_t(kMaxWavefrontQueueEntries / queue_per_pixel);
  EXPECT_EQ(wave.stats.tiles, (s.tile_pixels + tile - 1) / tile);
  expect_same_render(cornell, *cornell->camera(), s);
}

TEST(Wavefront, TracesTheMegakernelsRaysNodeForNode) {
  const auto cornell = cornell_box();
  RenderSettings s = small(2);
  s.traversal_stats = true;
  const RenderStats mega = render(cornell, *cornell->camera(), s, KernelOrganisation::Megakernel).stats;
  for (const Traversal walk : kWavefrontWalks) {
    SCOPED_TRACE(to_string(walk));
    const RenderStats wave = render(cornell, *cornell->camera(), s, KernelOrganisation::Wavefront, walk).stats;
    ASSERT_TRUE(mega.traversal && wave.traversal);
    EXPECT_GT(wave.traversal->nodes, 0u);
    EXPECT_EQ(mega.traversal->nodes, wave.traversal->nodes);
    EXPECT_EQ(mega.traversal->leaves, wave.traversal->leaves);
    EXPECT_EQ(mega.traversal->triangles, wave.traversal->triangles);
    EXPECT_EQ(mega.traversal->restarts, wave.traversal->restarts);
  }
}

// A bounce with more rays than a stream holds is cut into launches: r = 2^12
// at 24 x 24 gives bounce 1 2.4 million rays, more than the 2^21 a stream holds.
TEST(Wavefront, LanesCutALargeBounceIntoLaunches) {
  const auto cornell = cornell_box();
  RenderSettings s = small(1);
  s.width = s.height = 24;
  s.samples = 1 << 12;
  expect_same_render(cornell, *cornell->camera(), s);
}

}  // namespace
}  // namespace mbao
