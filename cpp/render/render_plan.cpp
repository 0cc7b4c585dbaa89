#include "render/render_plan.h"

#include <algorithm>

#include "mbao/gbuffer.h"
#include "mbao/limits.h"

namespace mbao {
namespace {

// The device table, each field named. Each entry's measurement is in
// docs/kernel-variants.md. Constant-initialized, so that other files' static
// objects may read it.
constexpr DeviceProfile cpu_profile() {
  DeviceProfile cpu;
  cpu.device_class = "CPU";
  cpu.walk = Traversal::Stack;
  cpu.min_lanes_depth = 16;
  cpu.organisation = KernelOrganisation::Megakernel;
  cpu.load_both_children = true;
  cpu.min_origin_path_depth = 16;
  cpu.shares_host_memory = true;
  cpu.min_indexed_triangles = std::size_t(1) << 22;
  cpu.gbuffer_packets = true;
  return cpu;
}

constexpr DeviceProfile gpu_profile() {
  DeviceProfile gpu;
  gpu.device_class = "GPU";
  gpu.walk = Traversal::ShortStack;
  gpu.organisation = KernelOrganisation::Wavefront;
  gpu.max_registers = 64;
  return gpu;
}

// Accelerators and others: unmeasured, so the GPU's walk without its wavefront.
constexpr DeviceProfile other_profile() {
  DeviceProfile other;
  other.device_class = "other";
  other.walk = Traversal::ShortStack;
  return other;
}

constexpr DeviceProfile kCpu = cpu_profile(), kGpu = gpu_profile(), kOther = other_profile();

bool walks_full_stack(Traversal walk) { return walk == Traversal::Stack || walk == Traversal::Lanes; }

bool deep_enough(int depth, int min_depth) { return min_depth > 0 && depth >= min_depth; }

std::string define(const char* name, int value) { return std::string(" -D") + name + "=" + std::to_string(value); }

std::string depth_reason(const SceneTraits& scene, int min_depth) {
  return "the tree is " + std::to_string(scene.tree_depth) + " deep, the profile's threshold " +
         std::to_string(min_depth);
}

// Auto's walk for a render; lanes only where the wavefront can run the settings.
Traversal plan_traversal(const RenderSettings& s, const DeviceProfile& profile, const SceneTraits& scene,
                         std::vector<std::string>& reasons) {
  if (s.traversal != Traversal::Auto) return s.traversal;
  const bool lanes_can_run =
      s.organisation != KernelOrganisation::Megakernel && s.wavefront_can_run() && !s.origin_paths.value_or(false);
  const bool lanes = deep_enough(scene.tree_depth, profile.min_lanes_depth) && lanes_can_run;
  const Traversal walk = lanes ? Traversal::Lanes : profile.walk;
  std::string why = "traversal " + to_string(walk) + ": the " + std::string(profile.device_class) + " profile's";
  if (profile.min_lanes_depth > 0)
    why += lanes ? " lanes (" + depth_reason(scene, profile.min_lanes_depth) + ")"
                 : " walk of one ray (lanes need a tree at least " + std::to_string(profile.min_lanes_depth) +
                       " deep and the wavefront; " + depth_reason(scene, profile.min_lanes_depth) + ")";
  reasons.push_back(why);
  return walk;
}

// HBAO's walk: that of its G-buffer's camera rays, which run in packets
// (lanes) without the wavefront.
Traversal plan_gbuffer_traversal(const RenderSettings& s, const DeviceProfile& profile,
                                 std::vector<std::string>& reasons) {
  if (s.traversal != Traversal::Auto) return s.traversal;
  const Traversal walk = profile.gbuffer_packets ? Traversal::Lanes : profile.walk;
  reasons.push_back("traversal " + to_string(walk) + ": the G-buffer's camera rays, " +
                    (profile.gbuffer_packets ? "in packets" : "one per work item") + " on the " + profile.device_class +
                    " profile");
  return walk;
}

KernelOrganisation plan_organisation(const RenderSettings& s, FrameOutput output, Traversal traversal,
                                     const DeviceProfile& profile, std::vector<std::string>& reasons) {
  if (output != FrameOutput::AmbientOcclusion) return KernelOrganisation::Megakernel;  // camera rays alone
  if (s.organisation != KernelOrganisation::Auto) return s.organisation;
  KernelOrganisation organisation = KernelOrganisation::Megakernel;
  std::string why;
  if (traversal == Traversal::Lanes) {
    organisation = KernelOrganisation::Wavefront;
    why = "lanes run in the wavefront";
  } else if (profile.organisation == KernelOrganisation::Wavefront && s.wavefront_can_run()) {
    organisation = KernelOrganisation::Wavefront;
    why = "the " + std::string(profile.device_class) + " profile's";
  } else {
    why = profile.organisation == KernelOrganisation::Wavefront
              ? "the wavefront cannot run these settings"
              : "the " + std::string(profile.device_class) + " profile's";
  }
  reasons.push_back("organisation " + to_string(organisation) + ": " + why);
  return organisation;
}

int plan_register_cap(const DeviceInfo& device, const DeviceProfile& profile, std::vector<std::string>& reasons) {
  if (profile.max_registers == 0) return 0;
  if (!device.nvidia_compiler_options) {
    reasons.push_back("registers: the compiler's choice (the device's compiler takes no cap)");
    return 0;
  }
  reasons.push_back("registers: at most " + std::to_string(profile.max_registers) +
                    " per work item (cl_nv_compiler_options)");
  return profile.max_registers;
}

bool indexed_triangles(const DeviceProfile& profile, std::size_t triangles) {
  return profile.shares_host_memory && profile.min_indexed_triangles > 0 && triangles >= profile.min_indexed_triangles;
}

bool plan_origin_paths(const RenderSettings& s, FrameOutput output, Traversal walk, const DeviceProfile& profile,
                       const SceneTraits& scene, std::vector<std::string>& reasons) {
  if (walk == Traversal::Lanes || output != FrameOutput::AmbientOcclusion) return false;
  if (s.origin_paths) return *s.origin_paths;
  const bool paths = deep_enough(scene.tree_depth, profile.min_origin_path_depth);
  if (profile.min_origin_path_depth > 0)
    reasons.push_back(std::string("origin paths ") + (paths ? "on" : "off") + ": " +
                      depth_reason(scene, profile.min_origin_path_depth));
  return paths;
}

// Tiles are sized so one launch holds at most this many camera samples (16 MiB
// of hit records) and traces at most this many rays, whatever r^b is; the
// wavefront's queues hold at most kMaxWavefrontQueueEntries. 2^24 rays are
// enough to fill a GPU and take a second or two on a CPU, which is how long
// Ctrl-C may wait for the tile in flight.
constexpr std::size_t kMaxTileCameraSamples = std::size_t(1) << 20;
constexpr std::uint64_t kMaxTileRays = std::uint64_t(1) << 24;

// The most pixels whose wavefront queues fit kMaxWavefrontQueueEntries (>= 1:
// validate() refuses more per pixel); no limit for the megakernel.
std::size_t queue_limited_pixels(const RenderSettings& s, KernelOrganisation organisation, std::size_t pixels) {
  if (organisation != KernelOrganisation::Wavefront) return pixels;
  const std::uint64_t per_pixel =
      std::max<std::uint64_t>(1, s.max_queue_entries_per_camera_sample()) * std::uint64_t(s.spp);
  return std::min(pixels, std::size_t(kMaxWavefrontQueueEntries / per_pixel));
}

// A tile asked for is cut down only where the wavefront's queues would not fit.
std::size_t tile_pixels_for(const RenderSettings& s, KernelOrganisation organisation) {
  const std::size_t pixels = std::size_t(s.width) * std::size_t(s.height);
  const std::size_t limit = queue_limited_pixels(s, organisation, pixels);
  if (s.tile_pixels) return std::min(s.tile_pixels, limit);
  const std::uint64_t rays_per_pixel =
      std::max<std::uint64_t>(1, s.max_rays_per_camera_sample()) * std::uint64_t(s.spp);
  const std::size_t by_memory = kMaxTileCameraSamples / std::size_t(s.spp);
  const std::size_t by_rays = std::size_t(std::max<std::uint64_t>(1, kMaxTileRays / rays_per_pixel));
  return std::max<std::size_t>(1, std::min({limit, by_memory, by_rays}));
}

FrameOutput frame_output(const RenderSettings& s, RenderProduct product) {
  if (product == RenderProduct::GBuffer) return FrameOutput::GBuffer;
  return s.method == Method::Hbao ? FrameOutput::HbaoGBuffer : FrameOutput::AmbientOcclusion;
}

// The G-buffer planes the frame's camera rays write: those its readers read.
std::uint32_t gbuffer_planes(const RenderSettings& s, FrameOutput output) {
  switch (output) {
    case FrameOutput::GBuffer: return MBAO_GBUFFER_ALL_PLANES;
    case FrameOutput::HbaoGBuffer: return MBAO_GBUFFER_HBAO_PLANES;
    case FrameOutput::AmbientOcclusion: break;
  }
  return s.filtered() ? MBAO_GBUFFER_FILTER_PLANES : 0u;
}

FrameKernels frame_kernels(const RenderSettings& s, const RenderPlan& plan) {
  FrameKernels k;
  // Lanes take the camera rays in packets (kernels/kd_packet.h), one packet per work item.
  const bool packets = plan.traversal == Traversal::Lanes;
  k.camera_rays = packets ? "trace_camera_packets" : "trace_camera_rays";
  k.camera_samples_per_item = packets ? MBAO_LANES : 1;
  if (plan.output != FrameOutput::AmbientOcclusion) return k;
  if (plan.organisation == KernelOrganisation::Megakernel) {
    k.ao = AoLaunches::Megakernel;
    k.megakernel = s.estimator == Estimator::Branching ? "ao_branching" : "ao_path";
    return k;
  }
  k.ao = plan.traversal == Traversal::Lanes ? AoLaunches::StreamedWavefront : AoLaunches::Wavefront;
  if (k.ao == AoLaunches::StreamedWavefront) {
    k.stream_rays = "stream_bounce_rays";
    k.stream_trace = "trace_rays_in_lanes";
    k.stream_hits = "stream_bounce_hits";
  } else {
    k.first_bounce = "wavefront_first_bounce";
    k.bounce = "wavefront_bounce";
  }
  k.finish = "wavefront_finish";
  return k;
}

}  // namespace

std::vector<std::string> FrameKernels::in_launch_order() const {
  std::vector<std::string> names;
  for (const std::string* name :
       {&camera_rays, &megakernel, &first_bounce, &bounce, &stream_rays, &stream_trace, &stream_hits, &finish})
    if (!name->empty()) names.push_back(*name);
  return names;
}

const DeviceProfile& device_profile(const DeviceInfo& device) {
  if (device.type == "CPU") return kCpu;
  if (device.type == "GPU") return kGpu;
  return kOther;
}

SceneTraits SceneTraits::of(const Scene& scene) {
  SceneTraits traits;
  traits.tree_depth = scene.kd_tree()->stats.max_depth;
  traits.triangles = scene.mesh().triangles.size();
  traits.alpha_masks = !scene.masks().empty();
  traits.vertex_normals = scene.mesh().has_normals();
  return traits;
}

const char* ProgramVariant::file() const {
  switch (program) {
    case Program::Render: return "render.cl";
    case Program::Trace: return "trace.cl";
    case Program::Hbao: return "hbao.cl";
    case Program::Denoise: return "denoise.cl";
    case Program::Temporal: return "temporal.cl";
  }
  return "";
}

std::string ProgramVariant::options() const {
  if (program == Program::Hbao || program == Program::Denoise || program == Program::Temporal) return "";
  std::string o = define("MBAO_TRAVERSAL", int(walk)).substr(1);
  o += define("MBAO_COUNT_TRAVERSAL", count_traversal);
  o += define("MBAO_ALPHA_MASKS", alpha_masks);
  o += define("MBAO_LOAD_BOTH_CHILDREN", load_both_children);
  if (program == Program::Render) o += define("MBAO_ORIGIN_PATHS", origin_paths);
  o += define("MBAO_INDEXED_TRIANGLES", indexed_triangles);
  if (max_registers > 0) o += " -cl-nv-maxrregcount=" + std::to_string(max_registers);
  return o;
}

std::vector<ProgramVariant> all_program_variants() {
  std::vector<ProgramVariant> variants;
  const Traversal walks[] = {Traversal::Restart, Traversal::PushDown, Traversal::ShortStack, Traversal::Stack,
                             Traversal::Lanes};
  for (Program program : {Program::Render, Program::Trace}) {
    const bool render = program == Program::Render;
    for (Traversal walk : walks) {
      for (int bits = 0; bits < 32; ++bits) {
        ProgramVariant v;
        v.program = program;
        v.walk = walk;
        v.count_traversal = bits & 1;
        v.alpha_masks = bits & 2;
        v.load_both_children = bits & 4;
        v.origin_paths = bits & 8;
        v.indexed_triangles = bits & 16;
        // Only the bits that the program reads, and only where the plan can set them.
        if ((v.load_both_children && !walks_full_stack(walk)) ||
            (v.origin_paths && (!render || walk == Traversal::Lanes)))
          continue;
        variants.push_back(v);
      }
    }
  }
  for (Program program : {Program::Hbao, Program::Denoise, Program::Temporal}) {
    ProgramVariant screen_space;
    screen_space.program = program;
    variants.push_back(screen_space);
  }
  return variants;
}

bool plans_indexed_triangles(const DeviceInfo& device, std::size_t triangles) {
  return indexed_triangles(device_profile(device), triangles);
}

RenderPlan plan_render(const RenderSettings& s, const DeviceInfo& device, const SceneTraits& scene,
                       RenderProduct product) {
  const DeviceProfile& profile = device_profile(device);
  RenderPlan plan;
  plan.output = frame_output(s, product);
  const bool camera_rays_only = plan.output != FrameOutput::AmbientOcclusion;
  plan.traversal = camera_rays_only ? plan_gbuffer_traversal(s, profile, plan.reasons)
                                    : plan_traversal(s, profile, scene, plan.reasons);
  plan.organisation = plan_organisation(s, plan.output, plan.traversal, profile, plan.reasons);
  plan.gbuffer_planes = gbuffer_planes(s, plan.output);
  plan.tile_pixels = tile_pixels_for(s, plan.organisation);
  plan.kernels = frame_kernels(s, plan);

  plan.shading_normals = s.normals == NormalMode::Shading && scene.vertex_normals;
  ProgramVariant& p = plan.program;
  p.program = Program::Render;
  p.walk = plan.traversal;
  p.count_traversal = s.traversal_stats;
  p.alpha_masks = scene.alpha_masks;
  p.load_both_children = profile.load_both_children && walks_full_stack(p.walk);
  p.origin_paths = plan_origin_paths(s, plan.output, p.walk, profile, scene, plan.reasons);
  p.indexed_triangles = indexed_triangles(profile, scene.triangles);
  p.max_registers = plan_register_cap(device, profile, plan.reasons);
  if (profile.min_indexed_triangles > 0)
    plan.reasons.push_back(std::string("triangles ") +
                           (p.indexed_triangles ? "from the mesh's vertices" : "as coordinates") + ": " +
                           std::to_string(scene.triangles) + " of them, the profile's threshold " +
                           std::to_string(profile.min_indexed_triangles));
  return plan;
}

ProgramVariant plan_trace(Traversal requested, bool count_traversal, const DeviceInfo& device,
                          const SceneTraits& scene) {
  const DeviceProfile& profile = device_profile(device);
  ProgramVariant p;
  p.program = Program::Trace;
  p.walk = requested != Traversal::Auto                             ? requested
           : deep_enough(scene.tree_depth, profile.min_lanes_depth) ? Traversal::Lanes
                                                                    : profile.walk;
  p.count_traversal = count_traversal;
  p.alpha_masks = scene.alpha_masks;
  p.load_both_children = profile.load_both_children && walks_full_stack(p.walk);
  p.indexed_triangles = indexed_triangles(profile, scene.triangles);
  return p;
}

}  // namespace mbao
