// What "auto" runs (render/render_plan.h), device class by device class, and
// what each program is compiled with. The images do not depend on the plan:
// test_wavefront.cpp, test_origin_paths.cpp and tests/test_traversal.py
// compare the variants' images and hits.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "mbao/gbuffer.h"
#include "mbao/limits.h"
#include "render/render_plan.h"
#include "render/renderer.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

DeviceInfo device_of_type(const char* type) {
  DeviceInfo device;
  device.type = type;
  return device;
}
const DeviceInfo kCpu = device_of_type("CPU"), kGpu = device_of_type("GPU"),
                 kAccelerator = device_of_type("accelerator");

SceneTraits tree_of_depth(int depth) {
  SceneTraits scene;
  scene.tree_depth = depth;
  return scene;
}
const int kLanesDepth = device_profile(kCpu).min_lanes_depth;
const SceneTraits kDeep = tree_of_depth(kLanesDepth), kShallow = tree_of_depth(kLanesDepth - 1);

RenderSettings two_bounces() {
  RenderSettings s;
  s.bounces = 2;
  return s;
}

TEST(RenderPlan, CpusWalkDeepTreesInLanesWhereTheWavefrontCanRunAndShallowOnesWithTheFullStack) {
  RenderSettings s = two_bounces();
  const RenderPlan deep = plan_render(s, kCpu, kDeep);
  EXPECT_EQ(deep.traversal, Traversal::Lanes);
  EXPECT_EQ(deep.organisation, KernelOrganisation::Wavefront);
  const RenderPlan shallow = plan_render(s, kCpu, kShallow);
  EXPECT_EQ(shallow.traversal, Traversal::Stack);
  EXPECT_EQ(shallow.organisation, KernelOrganisation::Megakernel);
  // Where lanes cannot run the settings, the full stack does.
  s.organisation = KernelOrganisation::Megakernel;
  EXPECT_EQ(plan_render(s, kCpu, kDeep).traversal, Traversal::Stack);
  s = two_bounces();
  s.estimator = Estimator::Path;
  EXPECT_EQ(plan_render(s, kCpu, kDeep).traversal, Traversal::Stack);
  s = two_bounces();
  s.origin_paths = true;
  EXPECT_EQ(plan_render(s, kCpu, kDeep).traversal, Traversal::Stack);
  // Ray queries take lanes by the tree's depth alone.
  EXPECT_EQ(plan_trace(Traversal::Auto, false, kCpu, kDeep).walk, Traversal::Lanes);
  EXPECT_EQ(plan_trace(Traversal::Auto, false, kCpu, kShallow).walk, Traversal::Stack);
}

TEST(RenderPlan, GpusRunTheShortStackInTheWavefrontWhereItCanRunTheSettings) {
  RenderSettings s = two_bounces();
  EXPECT_EQ(plan_render(s, kGpu, kDeep).traversal, Traversal::ShortStack);
  EXPECT_EQ(plan_render(s, kGpu, kDeep).organisation, KernelOrganisation::Wavefront);
  EXPECT_EQ(plan_trace(Traversal::Auto, false, kGpu, kDeep).walk, Traversal::ShortStack);
  s.estimator = Estimator::Path;
  EXPECT_EQ(plan_render(s, kGpu, kDeep).organisation, KernelOrganisation::Megakernel);
  // Other devices (unmeasured) take the GPU's walk in the megakernel.
  EXPECT_EQ(plan_render(two_bounces(), kAccelerator, kDeep).traversal, Traversal::ShortStack);
  EXPECT_EQ(plan_render(two_bounces(), kAccelerator, kDeep).organisation, KernelOrganisation::Megakernel);
}

TEST(RenderPlan, WhatIsAskedForByNameRunsOnAnyDevice) {
  RenderSettings s = two_bounces();
  s.organisation = KernelOrganisation::Megakernel;
  s.traversal = Traversal::Restart;
  EXPECT_EQ(plan_render(s, kGpu, kDeep).organisation, KernelOrganisation::Megakernel);
  EXPECT_EQ(plan_render(s, kGpu, kDeep).traversal, Traversal::Restart);
  s.organisation = KernelOrganisation::Wavefront;
  EXPECT_EQ(plan_render(s, kCpu, kShallow).organisation, KernelOrganisation::Wavefront);
  // Lanes run in the wavefront, which auto then picks on any device.
  s = two_bounces();
  s.traversal = Traversal::Lanes;
  EXPECT_EQ(plan_render(s, kCpu, kShallow).organisation, KernelOrganisation::Wavefront);
  EXPECT_EQ(plan_render(s, kGpu, kShallow).organisation, KernelOrganisation::Wavefront);
  EXPECT_EQ(plan_trace(Traversal::PushDown, false, kCpu, kDeep).walk, Traversal::PushDown);
}

TEST(RenderPlan, OriginPathsOnCpusForDeepTreesOnlyAndNeverInLanes) {
  RenderSettings s;
  s.traversal = Traversal::Stack;
  const int depth = device_profile(kCpu).min_origin_path_depth;
  EXPECT_TRUE(plan_render(s, kCpu, tree_of_depth(depth)).program.origin_paths);
  EXPECT_FALSE(plan_render(s, kCpu, tree_of_depth(depth - 1)).program.origin_paths);
  EXPECT_FALSE(plan_render(s, kGpu, tree_of_depth(depth)).program.origin_paths);
  s.origin_paths = true;
  EXPECT_TRUE(plan_render(s, kGpu, tree_of_depth(depth - 1)).program.origin_paths);
  s.origin_paths = false;
  EXPECT_FALSE(plan_render(s, kCpu, tree_of_depth(depth)).program.origin_paths);
  s = two_bounces();
  EXPECT_FALSE(plan_render(s, kCpu, kDeep).program.origin_paths);  // lanes
}

// The mesh's own vertices cost a CPU's walks 5-18% of a frame and save 48
// bytes a triangle: large scenes only, and never on a GPU.
TEST(RenderPlan, LargeScenesOnCpusReadTheMeshsOwnVertices) {
  const RenderSettings s;
  SceneTraits large = kShallow;
  large.triangles = std::size_t(1) << 22;
  SceneTraits smaller = large;
  smaller.triangles -= 1;
  EXPECT_TRUE(plan_render(s, kCpu, large).program.indexed_triangles);
  EXPECT_FALSE(plan_render(s, kCpu, smaller).program.indexed_triangles);
  EXPECT_FALSE(plan_render(s, kGpu, large).program.indexed_triangles);
  EXPECT_TRUE(plan_trace(Traversal::Auto, false, kCpu, large).indexed_triangles);
  EXPECT_FALSE(plan_trace(Traversal::Auto, false, kGpu, large).indexed_triangles);
  EXPECT_TRUE(plans_indexed_triangles(kCpu, large.triangles));
  EXPECT_FALSE(plans_indexed_triangles(kCpu, smaller.triangles));
}

TEST(RenderPlan, BothChildrenAreLoadedInTheFullStacksWalkOnCpusOnly) {
  RenderSettings s;
  for (const Traversal walk : {Traversal::Restart, Traversal::PushDown, Traversal::ShortStack, Traversal::Stack}) {
    s.traversal = walk;
    EXPECT_EQ(plan_render(s, kCpu, kShallow).program.load_both_children, walk == Traversal::Stack);
    EXPECT_FALSE(plan_render(s, kGpu, kShallow).program.load_both_children);
  }
  EXPECT_TRUE(plan_trace(Traversal::Lanes, false, kCpu, kDeep).load_both_children);
}

TEST(RenderPlan, EachProgramIsBuiltWithTheDefinesItReads) {
  SceneTraits scene = kDeep;
  scene.alpha_masks = scene.vertex_normals = true;
  RenderSettings s = two_bounces();
  s.traversal_stats = true;
  EXPECT_EQ(plan_render(s, kCpu, scene).program.options(),
            "-DMBAO_TRAVERSAL=4 -DMBAO_COUNT_TRAVERSAL=1 -DMBAO_ALPHA_MASKS=1 -DMBAO_LOAD_BOTH_CHILDREN=1 "
            "-DMBAO_ORIGIN_PATHS=0 -DMBAO_INDEXED_TRIANGLES=0");
  EXPECT_EQ(plan_trace(Traversal::Auto, true, kCpu, scene).options(),
            "-DMBAO_TRAVERSAL=4 -DMBAO_COUNT_TRAVERSAL=1 -DMBAO_ALPHA_MASKS=1 -DMBAO_LOAD_BOTH_CHILDREN=1 "
            "-DMBAO_INDEXED_TRIANGLES=0");
  // HBAO's G-buffer is render.cl's camera rays: its counts, but none of the AO's origin paths; the
  // screen-space pass reads no define.
  s.method = Method::Hbao;
  s.bounces = 1;
  const RenderPlan hbao = plan_render(s, kCpu, scene);
  EXPECT_STREQ(hbao.program.file(), "render.cl");
  EXPECT_EQ(hbao.program.options(),
            "-DMBAO_TRAVERSAL=4 -DMBAO_COUNT_TRAVERSAL=1 -DMBAO_ALPHA_MASKS=1 -DMBAO_LOAD_BOTH_CHILDREN=1 "
            "-DMBAO_ORIGIN_PATHS=0 -DMBAO_INDEXED_TRIANGLES=0");
  ProgramVariant screen_space;
  screen_space.program = Program::Hbao;
  EXPECT_STREQ(screen_space.file(), "hbao.cl");
  EXPECT_EQ(screen_space.options(), "");
  // Shading normals are no define: the scene goes to the device with its normals, or without.
  EXPECT_TRUE(hbao.shading_normals);
  s.normals = NormalMode::Geometric;
  EXPECT_FALSE(plan_render(s, kCpu, scene).shading_normals);
}

// HBAO's G-buffer traces only camera rays, coherent whatever the tree: in
// packets on CPUs, shallow trees included, and in the GPU profile's walk there.
TEST(RenderPlan, HbaoWalksItsCameraRaysAsTheProfileSays) {
  RenderSettings s = two_bounces();
  s.method = Method::Hbao;
  s.bounces = 1;
  s.max_distance = 2.0f;
  EXPECT_EQ(plan_render(s, kCpu, kShallow).traversal, Traversal::Lanes);
  EXPECT_EQ(plan_render(s, kCpu, kDeep).traversal, Traversal::Lanes);
  EXPECT_EQ(plan_render(s, kGpu, kDeep).traversal, Traversal::ShortStack);
  EXPECT_EQ(plan_render(s, kCpu, kShallow).organisation, KernelOrganisation::Megakernel);
  s.traversal = Traversal::Stack;
  EXPECT_EQ(plan_render(s, kCpu, kDeep).traversal, Traversal::Stack);
}

// Every plan, over a grid of settings, devices and scenes, builds a variant
// that all_program_variants lists: the list the OpenCL C 1.2 test compiles.
TEST(RenderPlan, EveryPlannedProgramIsAListedVariant) {
  std::set<std::string> listed;
  for (const ProgramVariant& v : all_program_variants()) {
    EXPECT_TRUE(listed.insert(std::string(v.file()) + " " + v.options()).second) << v.file() << " " << v.options();
  }
  const auto expect_listed = [&](const ProgramVariant& v) {
    EXPECT_EQ(listed.count(std::string(v.file()) + " " + v.options()), 1u) << v.file() << " " << v.options();
  };
  for (const DeviceInfo& device : {kCpu, kGpu, kAccelerator})
    for (int traits = 0; traits < 8; ++traits) {
      SceneTraits scene = traits & 1 ? kDeep : kShallow;
      scene.alpha_masks = traits & 2;
      scene.vertex_normals = traits & 4;
      for (const Traversal t : {Traversal::Restart, Traversal::PushDown, Traversal::ShortStack, Traversal::Stack,
                                Traversal::Lanes, Traversal::Auto}) {
        for (const bool count : {false, true}) expect_listed(plan_trace(t, count, device, scene));
        for (int bits = 0; bits < 32; ++bits) {
          RenderSettings s = two_bounces();
          s.traversal = t;
          s.traversal_stats = bits & 1;
          if (bits & 2) s.max_distance = 1.0f;
          s.normals = bits & 4 ? NormalMode::Geometric : NormalMode::Shading;
          s.method = bits & 8 ? Method::Hbao : Method::RayTraced;
          if (bits & 16 && t != Traversal::Lanes) s.origin_paths = !(bits & 1);
          expect_listed(plan_render(s, device, scene).program);
        }
      }
    }
}

using Kernels = std::vector<std::string>;

// The entry points a frame launches follow from the walk, the organisation,
// the estimator and what the frame makes; the frame reads them from the plan.
TEST(RenderPlan, NamesTheKernelsEachFrameLaunches) {
  RenderSettings s = two_bounces();
  EXPECT_EQ(plan_render(s, kCpu, kShallow).kernels.in_launch_order(), (Kernels{"trace_camera_rays", "ao_branching"}));
  EXPECT_EQ(plan_render(s, kCpu, kShallow).kernels.ao, AoLaunches::Megakernel);
  s.estimator = Estimator::Path;
  EXPECT_EQ(plan_render(s, kCpu, kShallow).kernels.in_launch_order(), (Kernels{"trace_camera_rays", "ao_path"}));
  s = two_bounces();
  EXPECT_EQ(plan_render(s, kGpu, kShallow).kernels.in_launch_order(),
            (Kernels{"trace_camera_rays", "wavefront_first_bounce", "wavefront_bounce", "wavefront_finish"}));
  EXPECT_EQ(plan_render(s, kGpu, kShallow).kernels.ao, AoLaunches::Wavefront);
  const RenderPlan lanes = plan_render(s, kCpu, kDeep);
  EXPECT_EQ(lanes.kernels.ao, AoLaunches::StreamedWavefront);
  EXPECT_EQ(lanes.kernels.in_launch_order(),
            (Kernels{"trace_camera_packets", "stream_bounce_rays", "trace_rays_in_lanes", "stream_bounce_hits",
                     "wavefront_finish"}));
  EXPECT_EQ(lanes.kernels.camera_samples_per_item, std::size_t(MBAO_LANES));
  EXPECT_EQ(plan_render(s, kGpu, kDeep).kernels.camera_samples_per_item, 1u);
}

// HBAO's frame and a G-buffer alone trace camera rays and nothing after them:
// each writes the planes its reader reads, a filtered image those of the filter.
TEST(RenderPlan, FramesOfCameraRaysAloneWriteThePlanesTheirReadersRead) {
  RenderSettings s = two_bounces();
  const RenderPlan image = plan_render(s, kCpu, kDeep);
  EXPECT_EQ(image.output, FrameOutput::AmbientOcclusion);
  EXPECT_EQ(image.gbuffer_planes, 0u);
  s.denoise = DenoiseSettings{};
  EXPECT_EQ(plan_render(s, kCpu, kDeep).gbuffer_planes, std::uint32_t(MBAO_GBUFFER_FILTER_PLANES));

  const RenderPlan gbuffer = plan_render(two_bounces(), kGpu, kDeep, RenderProduct::GBuffer);
  EXPECT_EQ(gbuffer.output, FrameOutput::GBuffer);
  EXPECT_EQ(gbuffer.gbuffer_planes, std::uint32_t(MBAO_GBUFFER_ALL_PLANES));
  EXPECT_EQ(gbuffer.organisation, KernelOrganisation::Megakernel);
  EXPECT_EQ(gbuffer.kernels.in_launch_order(), Kernels{"trace_camera_rays"});
  EXPECT_EQ(gbuffer.kernels.ao, AoLaunches::None);

  s = two_bounces();
  s.method = Method::Hbao;
  s.bounces = 1;
  const RenderPlan hbao = plan_render(s, kCpu, kShallow);
  EXPECT_EQ(hbao.output, FrameOutput::HbaoGBuffer);
  EXPECT_EQ(hbao.gbuffer_planes, std::uint32_t(MBAO_GBUFFER_HBAO_PLANES));
  EXPECT_EQ(hbao.kernels.in_launch_order(), Kernels{"trace_camera_packets"});  // the CPU's packets
  EXPECT_EQ(hbao.kernels.ao, AoLaunches::None);
  EXPECT_FALSE(hbao.program.origin_paths);
}

// A tile is a launch's worth of pixels: its hit records, its rays and, in
// the wavefront, its queue entries bounded, whatever r^b is.
TEST(RenderPlan, TilesHoldWhatOneLaunchMayHold) {
  RenderSettings s = two_bounces();
  s.width = s.height = 4096;
  s.samples = 16;
  s.bounces = 3;
  for (const DeviceInfo& device : {kCpu, kGpu}) {
    const RenderPlan plan = plan_render(s, device, kShallow);
    SCOPED_TRACE(to_string(plan.organisation));
    ASSERT_GT(plan.tile_pixels, 0u);
    EXPECT_LT(plan.tile_pixels, std::size_t(s.width * s.height));
    EXPECT_LE(plan.tile_pixels * s.max_rays_per_camera_sample(), std::uint64_t(1) << 24);
    if (plan.organisation == KernelOrganisation::Wavefront) {
      EXPECT_LE(plan.tile_pixels * s.max_queue_entries_per_camera_sample(), kMaxWavefrontQueueEntries);
    }
  }
  s.tile_pixels = 100;
  EXPECT_EQ(plan_render(s, kCpu, kShallow).tile_pixels, 100u);
}

// Where the device's compiler takes a register cap (NVIDIA's), render.cl is
// built with the GPU profile's; the cap is a build option, so the variants
// all_program_variants lists, and their sources, are the same with it and without.
TEST(RenderPlan, GpusWhoseCompilerTakesACapBuildRenderClWithTheProfilesRegisters) {
  DeviceInfo nvidia = kGpu, cpu = kCpu;
  nvidia.nvidia_compiler_options = cpu.nvidia_compiler_options = true;
  const RenderPlan capped = plan_render(two_bounces(), nvidia, kDeep);
  EXPECT_EQ(capped.program.max_registers, device_profile(kGpu).max_registers);
  EXPECT_GT(capped.program.max_registers, 0);
  ProgramVariant uncapped = capped.program;
  uncapped.max_registers = 0;
  EXPECT_EQ(capped.program.options(),
            uncapped.options() + " -cl-nv-maxrregcount=" + std::to_string(capped.program.max_registers));
  EXPECT_NE(capped.reasons.back().find("registers: at most"), std::string::npos);

  const RenderPlan other_gpu = plan_render(two_bounces(), kGpu, kDeep);
  EXPECT_EQ(other_gpu.program.max_registers, 0);
  EXPECT_EQ(other_gpu.program.options(), uncapped.options());
  EXPECT_NE(other_gpu.reasons.back().find("the compiler's choice"), std::string::npos);
  EXPECT_EQ(plan_render(two_bounces(), cpu, kDeep).program.max_registers, 0);  // measured on GPUs only
  EXPECT_EQ(plan_trace(Traversal::Auto, false, nvidia, kDeep).max_registers, 0);
}

TEST(RenderPlan, ReasonsNameEachAutomaticChoice) {
  const RenderPlan plan = plan_render(two_bounces(), kCpu, kDeep);
  // Traversal, organisation and the triangles' layout; lanes take no origin paths.
  ASSERT_EQ(plan.reasons.size(), 3u);
  EXPECT_NE(plan.reasons[0].find("traversal lanes"), std::string::npos);
  EXPECT_NE(plan.reasons[1].find("organisation wavefront"), std::string::npos);
  EXPECT_NE(plan.reasons[2].find("triangles as coordinates"), std::string::npos);
  RenderSettings named = two_bounces();
  named.traversal = Traversal::Stack;
  named.organisation = KernelOrganisation::Megakernel;
  named.origin_paths = false;
  const RenderPlan chosen = plan_render(named, kCpu, kDeep);
  ASSERT_EQ(chosen.reasons.size(), 1u);  // the layout, which no setting names
  EXPECT_NE(chosen.reasons[0].find("triangles as coordinates"), std::string::npos);
}

TEST(RenderPlan, TheRendererRunsThePlanAndSaysWhy) {
  const auto box = cornell_box();
  RenderSettings s;
  s.width = s.height = 8;
  Renderer& renderer = Renderer::for_device(default_device());
  const RenderPlan plan = plan_render(s, renderer.device(), SceneTraits::of(*box));
  const RenderResult result = renderer.render(box, *box->camera(), s);
  EXPECT_EQ(result.stats.kernel_options, plan.program.options());
  EXPECT_EQ(result.stats.traversal_mode, to_string(plan.traversal));
  EXPECT_EQ(result.stats.organisation, to_string(plan.organisation));
  EXPECT_EQ(result.stats.plan, plan.reasons);
}

}  // namespace
}  // namespace mbao
