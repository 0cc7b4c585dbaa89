#include "render/renderer.h"

#include <algorithm>
#include <map>
#include <optional>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/timer.h"
#include "mbao/gbuffer.h"
#include "mbao/pixel_order.h"
#include "opencl/launch.h"
#include "render/denoiser.h"
#include "render/frame.h"
#include "render/hbao_pass.h"

namespace mbao {
namespace {

// Points moved into the scene's device frame (Scene::render_origin).
std::vector<cl_float4> relative_to(const std::vector<cl_float4>& points, const glm::vec3& origin) {
  std::vector<cl_float4> moved(points);
  for (cl_float4& p : moved) {
    p.s[0] -= origin.x;
    p.s[1] -= origin.y;
    p.s[2] -= origin.z;
  }
  return moved;
}

std::string mib(std::size_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

// Refuses, before allocating, a frame that cannot fit beside the scene: an
// allocation failure mid-render says far less. Tiles bound everything but the
// image itself, so only large images get here.
void check_device_memory(const DeviceInfo& device, const DeviceScene& scene, std::size_t frame_bytes,
                         const RenderSettings& s) {
  const std::size_t available = device.device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
  if (scene.bytes() + frame_bytes <= available) return;
  throw DeviceError("rendering " + std::to_string(s.width) + "x" + std::to_string(s.height) + " needs " +
                    mib(scene.bytes() + frame_bytes) + " of device memory (scene " + mib(scene.bytes()) +
                    ", image and tile buffers " + mib(frame_bytes) + "), more than the " + mib(available) + " of " +
                    device.description());
}

}  // namespace

AoRadius radius_for(const RenderSettings& settings, const Camera& camera, const Scene& scene) {
  if (settings.max_distance) return {*settings.max_distance, "settings"};
  if (camera.max_distance) return {*camera.max_distance, "camera"};
  if (settings.method == Method::Hbao) return {0.25f * glm::length(scene.bounds().hi - scene.bounds().lo), "scene"};
  return {settings.radius(), "none"};
}

Renderer& Renderer::for_device(const DeviceInfo& device) {
  static std::mutex mutex;
  // Never destroyed: releasing OpenCL objects during static destruction can run
  // after the driver has been unloaded.
  static auto* renderers = new std::map<cl_device_id, std::unique_ptr<Renderer>>;
  std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<Renderer>& renderer = (*renderers)[device.device()];
  if (!renderer) renderer = std::make_unique<Renderer>(device);
  return *renderer;
}

RenderResult Renderer::render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                              const RenderSettings& settings, const TileCallback& between_tiles,
                              TemporalHistory* history) {
  RenderSettings s = settings;
  if (history) s.temporal = history->settings();
  return run(scene, camera, s, between_tiles, nullptr, history);
}

RenderResult Renderer::bake(const std::shared_ptr<const Scene>& scene, const RenderSettings& settings,
                            const TilePoints& points_of_tile, const TileCallback& between_tiles,
                            std::size_t first_position, std::size_t end_position) {
  if (settings.method != Method::RayTraced)
    throw std::invalid_argument("a bake traces rays: method must be \"raytraced\"");
  const BakeTiles tiles{points_of_tile, first_position, end_position};
  return run(scene, Camera{}, settings, between_tiles, &tiles);
}

RenderResult Renderer::gbuffer(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                               const RenderSettings& settings) {
  return run(scene, camera, settings, {}, nullptr, nullptr, RenderProduct::GBuffer);
}

RenderResult Renderer::run(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                           const RenderSettings& requested, const TileCallback& between_tiles,
                           const BakeTiles* bake_tiles, TemporalHistory* history, RenderProduct product) {
  RenderResult result;
  RenderStats& stats = result.stats;
  const AoRadius radius = radius_for(requested, camera, *scene);
  RenderSettings settings = requested;
  settings.max_distance = radius.value;
  stats.max_distance = radius.value;
  stats.max_distance_source = radius.source;
  settings.validate();
  camera.validate();
  std::lock_guard<std::mutex> lock(mutex_);

  stats.device = device().description();
  DeviceScene::check_fits(*scene, device().device, settings.normals == NormalMode::Shading,
                          plans_indexed_triangles(device(), scene->mesh().triangles.size()));
  stats.tree_reused = scene->has_kd_tree();
  stats.tree = DeviceScene::tree_within(*scene, device().device)->stats;
  stats.build_ms = stats.tree.build_ms;
  const bool gbuffer_only = product == RenderProduct::GBuffer;
  const RenderPlan plan = plan_render(settings, device(), SceneTraits::of(*scene), product);
  stats.traversal_mode = to_string(plan.traversal);
  stats.plan = plan.reasons;
  stats.kernels = plan.kernels.in_launch_order();
  Stopwatch upload_clock;
  const std::shared_ptr<const DeviceScene> device_scene =
      scenes_.get(compute_, scene, plan.shading_normals, plan.program.indexed_triangles);
  stats.upload_ms = upload_clock.elapsed_ms();

  const BuiltProgram built = compute_.programs().get(plan.program.file(), plan.program.options());
  stats.kernel_build_ms = built.build_ms;
  stats.kernel_cache = to_string(built.origin);
  stats.kernel_options = plan.program.options();

  const std::size_t pixels = std::size_t(settings.width) * std::size_t(settings.height);
  result.width = int(settings.width);
  result.height = int(settings.height);
  if (!gbuffer_only) {  // a G-buffer frame's image is its planes; the triangle plane says which pixels a ray hit
    result.ao.resize(pixels);
    result.coverage.resize(pixels);
  }
  const Camera local_camera = camera.relative_to(scene->render_origin());
  try {
    if (plan.output == FrameOutput::AmbientOcclusion)
      run_traced(*device_scene, built.program, local_camera, settings, plan, between_tiles, bake_tiles, history,
                 result);
    else
      run_gbuffer(*device_scene, built.program, local_camera, settings, plan, result);
  } catch (const cl::Error& e) {
    throw_device_error((bake_tiles ? "baking " : "rendering ") + scene->name() + " on " + device().description(), e);
  }
  if (!bake_tiles) stats.rays_primary = std::uint64_t(pixels) * std::uint64_t(settings.spp);
  return result;
}

void Renderer::run_traced(const DeviceScene& scene, const cl::Program& program, const Camera& camera,
                          const RenderSettings& settings, const RenderPlan& plan, const TileCallback& between_tiles,
                          const BakeTiles* bake_tiles, TemporalHistory* history, RenderResult& result) {
  RenderStats& stats = result.stats;
  stats.organisation = to_string(plan.organisation);
  const std::size_t pixels = result.ao.size();
  const std::size_t tile_pixels = plan.tile_pixels;
  std::vector<cl_uint> secondary_rays(pixels);
  cl::CommandQueue& queue = compute_.queue();
  const PrimarySurfaces primaries = bake_tiles ? PrimarySurfaces::GivenPoints : PrimarySurfaces::CameraHits;
  const std::size_t filter_bytes =
      (settings.denoise ? Denoiser::device_bytes(pixels) : 0) + (history ? TemporalHistory::device_bytes(pixels) : 0);
  check_device_memory(device(), scene, Frame::device_bytes(settings, plan, tile_pixels, primaries) + filter_bytes,
                      settings);
  Frame frame(compute_.context(), device().device, program, scene, camera, settings, plan, tile_pixels, primaries);
  stats.memory_bytes = scene.bytes() + frame.bytes() + filter_bytes;
  // Some drivers (PoCL) build a kernel at its first launch, for its work-group
  // size and its grid's size: launched empty first, counted as kernel build time.
  if (launched_.insert(frame.launch_signature()).second) {
    Stopwatch clock;
    frame.enqueue_empty_tiles(queue);
    queue.finish();
    stats.kernel_build_ms += clock.elapsed_ms();
  }
  Stopwatch clock;
  const std::size_t begin = bake_tiles ? std::min(bake_tiles->first_position, pixels) : 0;
  const std::size_t end = bake_tiles ? std::clamp(bake_tiles->end_position, begin, pixels) : pixels;
  const std::size_t tiles = (end - begin + tile_pixels - 1) / tile_pixels;
  std::vector<cl_uint4> points;
  for (std::size_t first = begin; first < end; first += tile_pixels) {
    const std::size_t count = std::min(tile_pixels, end - first);
    if (bake_tiles) {
      // Where nothing waits between tiles, drawn while the device works on the tile before.
      points.resize(count * std::size_t(settings.spp));
      bake_tiles->points(first, count, points);
      frame.enqueue_tile(queue, first, count, points);
    } else {
      frame.enqueue_tile(queue, first, count);
    }
    ++stats.tiles;
    if (between_tiles) {
      queue.finish();
      between_tiles(stats.tiles, tiles);
    }
  }
  run_screen_space_passes(frame, camera, settings, history, result);
  if (bake_tiles) result.ao_second_moment.resize(pixels);
  if (settings.variance) result.variance.resize(pixels);
  frame.enqueue_read_back(queue, result, secondary_rays.data());
  queue.finish();
  stats.frame_ms = clock.elapsed_ms();
  if (settings.traversal_stats) stats.traversal = frame.traversal_totals(queue);
  if (begin == 0 && end == pixels) {
    for (cl_uint r : secondary_rays) stats.rays_secondary += r;
  } else {  // the other pixels hold what the device's buffer held
    const auto width = std::uint32_t(settings.width), height = std::uint32_t(settings.height);
    for (std::size_t p = begin; p < end; ++p)
      stats.rays_secondary += secondary_rays[pixel_at_position(std::uint32_t(p), width, height)];
  }
}

void Renderer::run_screen_space_passes(Frame& frame, const Camera& camera, const RenderSettings& settings,
                                       TemporalHistory* history, RenderResult& result) {
  RenderStats& stats = result.stats;
  cl::CommandQueue& queue = compute_.queue();
  const FrameBuffers& images = frame.buffers();
  if (history) {
    const cl::Program program = screen_space_program(Program::Temporal, stats);
    queue.finish();  // each pass's time apart from the AO's
    Stopwatch clock;
    history->enqueue_accumulate(queue, compute_.context(), program, images, CameraArgs(camera, settings),
                                settings.work_group_size);
    queue.finish();
    stats.temporal_ms = clock.elapsed_ms();
    result.history_length.resize(result.ao.size());
    history->enqueue_read_lengths(queue, result.history_length);
  }
  if (settings.denoise) {
    const cl::Program program = screen_space_program(Program::Denoise, stats);
    Denoiser denoiser(compute_.context(), device().device, program, std::size_t(settings.width),
                      std::size_t(settings.height), *settings.denoise, settings.work_group_size);
    queue.finish();
    Stopwatch clock;
    denoiser.enqueue(queue, images.gbuffer, images.ao, images.ao_variance);
    queue.finish();
    stats.denoise_ms = clock.elapsed_ms();
  }
}

cl::Program Renderer::screen_space_program(Program program, RenderStats& stats) {
  ProgramVariant variant;
  variant.program = program;
  const BuiltProgram built = compute_.programs().get(variant.file(), variant.options());
  stats.kernel_build_ms += built.build_ms;
  return built.program;
}

void Renderer::run_gbuffer(const DeviceScene& scene, const cl::Program& program, const Camera& camera,
                           const RenderSettings& settings, const RenderPlan& plan, RenderResult& result) {
  RenderStats& stats = result.stats;
  cl::CommandQueue& queue = compute_.queue();
  const std::size_t pixels = std::size_t(settings.width) * std::size_t(settings.height);
  const std::size_t tile_pixels = plan.tile_pixels;
  check_device_memory(device(), scene, Frame::device_bytes(settings, plan, tile_pixels), settings);
  Frame frame(compute_.context(), device().device, program, scene, camera, settings, plan, tile_pixels);
  std::optional<cl::Program> hbao_program;
  std::optional<HbaoPass> hbao;
  if (plan.output == FrameOutput::HbaoGBuffer) {
    hbao_program = screen_space_program(Program::Hbao, stats);
    hbao.emplace(device().device, *hbao_program, camera, settings);
  }
  stats.memory_bytes = scene.bytes() + frame.bytes();
  const auto enqueue_gbuffer = [&] {
    for (std::size_t first = 0; first < pixels; first += tile_pixels)
      frame.enqueue_tile(queue, first, std::min(tile_pixels, pixels - first));
  };
  // As in run_traced, a first launch builds the kernels on some drivers, for
  // the grid's size too; the HBAO pass has no empty launch, so the first frame
  // of each image size is counted as kernel build time.
  const std::string signature =
      frame.launch_signature() +
      (hbao ? " hbao " + std::to_string(reinterpret_cast<std::uintptr_t>((*hbao_program)())) : "") + " " +
      std::to_string(settings.width) + "x" + std::to_string(settings.height);
  if (launched_.insert(signature).second) {
    Stopwatch clock;
    enqueue_gbuffer();
    if (hbao) hbao->enqueue(queue, frame.buffers());
    queue.finish();
    stats.kernel_build_ms += clock.elapsed_ms();
  }
  Stopwatch clock;
  enqueue_gbuffer();
  stats.tiles = (pixels + tile_pixels - 1) / tile_pixels;
  queue.finish();  // the G-buffer's share of the frame apart
  stats.gbuffer_ms = clock.elapsed_ms();
  if (hbao) {
    hbao->enqueue(queue, frame.buffers());
    frame.enqueue_read_back(queue, result, nullptr);
  } else {
    result.gbuffer.resize(pixels * GBUFFER_PLANES);
    read_buffer(queue, frame.buffers().gbuffer, false, 0, result.gbuffer.size() * sizeof(float), result.gbuffer.data());
  }
  queue.finish();
  stats.frame_ms = clock.elapsed_ms();
  if (settings.traversal_stats) stats.traversal = frame.traversal_totals(queue);
}

TraceResult Renderer::trace(const std::shared_ptr<const Scene>& scene, const std::vector<cl_float4>& origins,
                            const std::vector<cl_float4>& directions, bool any_hit, Traversal traversal,
                            bool traversal_stats) {
  if (origins.size() != directions.size())
    throw std::invalid_argument("trace: " + std::to_string(origins.size()) + " origins but " +
                                std::to_string(directions.size()) + " directions");
  TraceResult result;
  result.hits.resize(origins.size());
  if (traversal_stats) result.counts.resize(origins.size());
  if (origins.empty()) return result;
  std::lock_guard<std::mutex> lock(mutex_);
  DeviceScene::check_fits(*scene, device().device, false,
                          plans_indexed_triangles(device(), scene->mesh().triangles.size()));
  DeviceScene::tree_within(*scene, device().device);
  const ProgramVariant variant = plan_trace(traversal, traversal_stats, device(), SceneTraits::of(*scene));
  const std::shared_ptr<const DeviceScene> device_scene =
      scenes_.get(compute_, scene, false, variant.indexed_triangles);
  const BuiltProgram built = compute_.programs().get(variant.file(), variant.options());
  static_assert(sizeof(RayHit) == sizeof(cl_uint4), "RayHit mirrors the kernel's uint4 hit record");
  try {
    const cl::Context& context = compute_.context();
    cl::CommandQueue& queue = compute_.queue();
    const std::size_t n = origins.size();
    std::vector<cl_float4> local_origins = relative_to(origins, scene->render_origin());
    cl::Buffer origin_buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float4),
                             local_origins.data());
    cl::Buffer direction_buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float4),
                                const_cast<cl_float4*>(directions.data()));
    cl::Buffer hit_buffer(context, CL_MEM_WRITE_ONLY, n * sizeof(cl_uint4));
    cl::Buffer count_buffer;
    if (traversal_stats) count_buffer = cl::Buffer(context, CL_MEM_WRITE_ONLY, n * sizeof(cl_uint4));
    const bool lanes = variant.walk == Traversal::Lanes;
    cl::Kernel kernel(built.program, lanes ? "trace_rays_in_lanes" : "trace_rays");
    const std::size_t group = work_group_size_for(kernel, device().device, 0);
    const std::size_t rays_per_item = lanes ? rays_per_lane_item(n, device().device, group) : 1;
    if (lanes)  // no frame totals here
      set_kernel_args(kernel, *device_scene, origin_buffer, direction_buffer, cl_uint(n), cl_int(any_hit),
                      cl_uint(rays_per_item), hit_buffer, count_buffer, cl::Buffer());
    else
      set_kernel_args(kernel, *device_scene, origin_buffer, direction_buffer, cl_uint(n), cl_int(any_hit), hit_buffer,
                      count_buffer);
    launch(queue, kernel, (n + rays_per_item - 1) / rays_per_item, group);
    read_buffer(queue, hit_buffer, true, 0, n * sizeof(cl_uint4), result.hits.data());
    if (traversal_stats) read_buffer(queue, count_buffer, true, 0, n * sizeof(cl_uint4), result.counts.data());
  } catch (const cl::Error& e) {
    throw_device_error("tracing rays in " + scene->name() + " on " + device().description(), e);
  }
  return result;
}

}  // namespace mbao
