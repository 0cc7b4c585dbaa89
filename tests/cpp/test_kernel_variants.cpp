// Every build of render.cl that a plan can ask for (all_program_variants),
// in every organisation it runs in, draws the same image bit for bit, with the
// same rays, and the variants of one walk count the same traversal work. The
// variants of a walk differ in where their nodes come from (origin paths,
// both children loaded), where their triangles come from (their coordinates or
// the mesh's vertices) or how rays are batched (lanes), never in a hit. Those
// that keep direction moments estimate the same variances too (SPEC 7.1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "opencl/compute_context.h"
#include "opencl/devices.h"
#include "random_soup.h"
#include "render/device_scene.h"
#include "render/frame.h"
#include "render/render_plan.h"
#include "scene/gltf_loader.h"

namespace mbao {
namespace {

struct Image {
  RenderResult result;
  std::uint64_t rays = 0;
  TraversalTotals counts;
};

// `variant`'s frame, in the organisation `s` names.
Image render(ComputeContext& compute, const ProgramVariant& variant, const DeviceScene& scene,
             const SceneTraits& traits, const Camera& camera, RenderSettings s) {
  s.traversal = variant.walk;
  const cl::Program& program = compute.programs().get(variant.file(), variant.options()).program;
  const std::size_t pixels = std::size_t(s.width * s.height);
  const RenderPlan plan = plan_render(s, compute.device(), traits);
  Frame frame(compute.context(), compute.device().device, program, scene, camera, s, plan, pixels);
  Image image;
  image.result.ao.resize(pixels);
  image.result.coverage.resize(pixels);
  if (s.variance) image.result.variance.resize(pixels);
  std::vector<cl_uint> rays(pixels);
  cl::CommandQueue& queue = compute.queue();
  frame.enqueue_tile(queue, 0, pixels);
  frame.enqueue_read_back(queue, image.result, rays.data());
  queue.finish();
  for (cl_uint r : rays) image.rays += r;
  image.counts = frame.traversal_totals(queue);
  return image;
}

bool same_counts(const TraversalTotals& a, const TraversalTotals& b) {
  return a.nodes == b.nodes && a.leaves == b.leaves && a.triangles == b.triangles && a.restarts == b.restarts;
}

TEST(KernelVariants, EveryRenderVariantOfThePlanDrawsTheSameImage) {
  ComputeContext compute(default_device());
  // Far from the world's origin, so that both triangle layouts move the vertices to the render origin.
  TriangleMesh soup = random_soup(3000, 5);
  for (glm::vec3& p : soup.positions) p += glm::vec3(1000.0f, 0.0f, 0.0f);
  const auto scene = std::make_shared<const Scene>(std::move(soup), "soup");
  ASSERT_EQ(scene->render_origin().x, scene->bounds().lo.x);
  const SceneTraits traits = SceneTraits::of(*scene);
  ASSERT_GE(traits.tree_depth, 16);  // deep enough for the short stack to run dry and paths to be long
  // The triangles as a GPU reads them (their coordinates) and as a CPU does (the mesh's vertices).
  const bool shares_host_memory = device_profile(compute.device()).shares_host_memory;
  const DeviceScene coordinates(compute.context(), compute.queue(), *scene, scene->kd_tree(), false, shares_host_memory,
                                false);
  const DeviceScene indexed(compute.context(), compute.queue(), *scene, scene->kd_tree(), false, true, true);
  const Camera camera = scene->default_camera(1.0f).relative_to(scene->render_origin());
  RenderSettings s;
  s.width = s.height = 24;
  s.bounces = 2;
  s.samples = 3;
  s.seed = 17;
  s.traversal_stats = true;

  std::unique_ptr<Image> first;
  std::vector<float> first_variance;
  std::map<Traversal, TraversalTotals> counts_of_walk;
  std::size_t rendered = 0;
  for (const ProgramVariant& v : all_program_variants()) {
    // This scene's and these settings' variants: every walk and device tuning.
    if (v.program != Program::Render || !v.count_traversal || v.alpha_masks != traits.alpha_masks) continue;
    for (const KernelOrganisation organisation : {KernelOrganisation::Megakernel, KernelOrganisation::Wavefront}) {
      if (v.walk == Traversal::Lanes && organisation == KernelOrganisation::Megakernel) continue;
      for (const bool direction_moments : {false, true}) {
        SCOPED_TRACE(v.options() + " " + to_string(organisation) +
                     (direction_moments ? " with direction moments" : " without direction moments"));
        s.organisation = organisation;
        s.variance = direction_moments;
        ASSERT_EQ(s.direction_moments(), direction_moments);
        const Image image = render(compute, v, v.indexed_triangles ? indexed : coordinates, traits, camera, s);
        ++rendered;
        const std::vector<float>& ao = image.result.ao;
        if (!first) {
          first = std::make_unique<Image>(image);
          double sum = 0.0;
          for (float a : ao) sum += a;
          ASSERT_GT(image.rays, 0u);
          ASSERT_LT(sum, double(ao.size()));  // not a vacuous agreement: light was blocked
        }
        EXPECT_EQ(std::memcmp(ao.data(), first->result.ao.data(), ao.size() * sizeof(float)), 0);
        EXPECT_EQ(image.result.coverage, first->result.coverage);
        EXPECT_EQ(image.rays, first->rays);
        if (direction_moments) {
          const std::vector<float>& variance = image.result.variance;
          if (first_variance.empty()) {
            first_variance = variance;
            ASSERT_GT(*std::max_element(variance.begin(), variance.end()), 0.0f);  // not vacuous either
          }
          EXPECT_EQ(std::memcmp(variance.data(), first_variance.data(), variance.size() * sizeof(float)), 0);
        }
        // Lanes walk the full stack: its counts, node for node.
        const Traversal walk = v.walk == Traversal::Lanes ? Traversal::Stack : v.walk;
        const auto [known, inserted] = counts_of_walk.emplace(walk, image.counts);
        if (!inserted) {
          EXPECT_TRUE(same_counts(image.counts, known->second));
        }
      }
    }
  }
  // 12 walks and tunings, lanes in the wavefront only, each with and without direction moments and of either
  // triangle layout
  EXPECT_EQ(rendered, 88u);
}

// Sponza's alpha masks and shading normals read the triangles' corners and
// vertex ids too: the same image from either layout, bit for bit.
TEST(KernelVariants, SponzaIsTheSameImageFromEitherTriangleLayout) {
  const char* shared = std::getenv("MBAO_SHARED_SCENES");
  const std::filesystem::path folder =
      (shared ? std::filesystem::path(shared)
              : std::filesystem::path(MBAO_SOURCE_DIR).parent_path() / "shared" / "scenes") /
      "sponza";
  if (!std::filesystem::exists(folder / "scene.glb")) GTEST_SKIP() << "no shared scene at " << folder;
  ComputeContext compute(default_device());
  const std::shared_ptr<const Scene> sponza = load_gltf((folder / "scene.glb").string());
  const Camera camera = Camera::load((folder / "camera.json").string()).relative_to(sponza->render_origin());
  RenderSettings s;
  s.width = s.height = 32;
  s.bounces = 2;
  s.samples = 2;
  s.max_distance = *camera.max_distance;
  s.traversal_stats = true;
  const SceneTraits traits = SceneTraits::of(*sponza);
  RenderPlan plan = plan_render(s, compute.device(), traits);
  ASSERT_TRUE(plan.program.alpha_masks && plan.shading_normals);
  const bool shares_host_memory = device_profile(compute.device()).shares_host_memory;
  const DeviceScene coordinates(compute.context(), compute.queue(), *sponza, sponza->kd_tree(), true,
                                shares_host_memory, false);
  const DeviceScene indexed(compute.context(), compute.queue(), *sponza, sponza->kd_tree(), true, true, true);
  s.organisation = plan.organisation;
  plan.program.indexed_triangles = false;
  const Image from_coordinates = render(compute, plan.program, coordinates, traits, camera, s);
  plan.program.indexed_triangles = true;
  const Image from_vertices = render(compute, plan.program, indexed, traits, camera, s);
  const std::vector<float>& ao = from_coordinates.result.ao;
  ASSERT_LT(*std::min_element(ao.begin(), ao.end()), 0.5f);  // not vacuous: corners occlude
  EXPECT_EQ(std::memcmp(ao.data(), from_vertices.result.ao.data(), ao.size() * sizeof(float)), 0);
  EXPECT_EQ(from_coordinates.rays, from_vertices.rays);
  EXPECT_TRUE(same_counts(from_coordinates.counts, from_vertices.counts));
}

}  // namespace
}  // namespace mbao
