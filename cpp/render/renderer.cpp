#include "render/renderer.h"

#include <algorithm>
#include <map>

#include "core/error.h"
#include "core/timer.h"

namespace mbao {
namespace {

// Tiles are sized so one launch holds at most this many camera samples (16 MiB
// of hit records) and traces at most this many rays, whatever r^b is.
constexpr std::size_t kMaxTileCameraSamples = std::size_t(1) << 20;
constexpr std::uint64_t kMaxTileRays = std::uint64_t(1) << 27;

std::string program_options(Traversal traversal) {
  return "-DMBAO_TRAVERSAL=" + std::to_string(traversal == Traversal::PushDown ? 1 : 0);
}

cl_float4 to_float4(const glm::vec3& v) { return {{v.x, v.y, v.z, 0.0f}}; }

std::size_t tile_pixels_for(const RenderSettings& s, std::size_t pixels) {
  if (s.tile_pixels) return std::min(s.tile_pixels, pixels);
  const std::uint64_t rays_per_pixel = std::max<std::uint64_t>(1, s.max_rays_per_camera_sample()) * std::uint64_t(s.spp);
  const std::size_t by_memory = kMaxTileCameraSamples / std::size_t(s.spp);
  const std::size_t by_rays = std::size_t(std::max<std::uint64_t>(1, kMaxTileRays / rays_per_pixel));
  return std::max<std::size_t>(1, std::min({pixels, by_memory, by_rays}));
}

// The default work-group size: 64 work items suit divergent ray-tracing code on
// GPUs, and a fixed size spares PoCL a compile for every launch size.
constexpr std::size_t kDefaultWorkGroupSize = 64;

std::size_t work_group_size_for(const cl::Kernel& kernel, const cl::Device& device, std::size_t requested) {
  const std::size_t limit = kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device);
  if (requested > limit)
    throw std::invalid_argument("work_group_size must be at most " + std::to_string(limit) +
                                " on this device, got " + std::to_string(requested));
  return requested ? requested : std::min(kDefaultWorkGroupSize, limit);
}

// Launches `items` work items (at least one work group, so an empty launch still runs).
void launch(cl::CommandQueue& queue, const cl::Kernel& kernel, std::size_t items, std::size_t work_group) {
  const std::size_t groups = std::max<std::size_t>(1, (items + work_group - 1) / work_group);
  queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(groups * work_group), cl::NDRange(work_group));
}

}  // namespace

Renderer& Renderer::for_device(const DeviceInfo& device) {
  static std::mutex mutex;
  static auto* renderers = new std::map<cl_device_id, std::unique_ptr<Renderer>>;  // never destroyed, as contexts
  std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<Renderer>& renderer = (*renderers)[device.device()];
  if (!renderer) renderer = std::make_unique<Renderer>(ComputeContext::for_device(device));
  return *renderer;
}

RenderResult Renderer::render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                              const RenderSettings& settings) {
  settings.validate();
  camera.validate();
  std::lock_guard<std::mutex> lock(mutex_);

  RenderResult result;
  RenderStats& stats = result.stats;
  stats.device = device().description();
  stats.tree_reused = scene->has_kd_tree();
  stats.tree = scene->kd_tree()->stats;
  stats.build_ms = stats.tree.build_ms;

  const bool with_normals = settings.normals == NormalMode::Shading && scene->mesh().has_normals();
  Stopwatch upload_clock;
  const std::shared_ptr<const DeviceScene> device_scene = scenes_.get(*compute_, scene, with_normals);
  stats.upload_ms = upload_clock.elapsed_ms();

  const BuiltProgram built = compute_->programs().get("render.cl", program_options(settings.traversal));
  stats.kernel_build_ms = built.build_ms;
  stats.kernel_cache_hit = built.cache_hit;

  const std::size_t width = std::size_t(settings.width), height = std::size_t(settings.height);
  const std::size_t pixels = width * height, spp = std::size_t(settings.spp);
  const std::size_t tile_pixels = tile_pixels_for(settings, pixels);
  result.width = settings.width;
  result.height = settings.height;
  result.ao.resize(pixels);
  result.mask.resize(pixels);
  std::vector<cl_uint> rays(pixels);

  const CameraBasis basis(camera);
  const float aspect = float(width) / float(height);
  const cl_float2 film_scale = {{basis.tan_half_vfov * aspect, basis.tan_half_vfov}};
  const cl_uint2 seed = {{cl_uint(settings.seed & 0xFFFFFFFFu), cl_uint(settings.seed >> 32)}};

  try {
    const cl::Context& context = compute_->context();
    cl::CommandQueue& queue = compute_->queue();
    cl::Buffer camera_hits(context, CL_MEM_READ_WRITE, tile_pixels * spp * sizeof(cl_uint4));
    cl::Buffer ao(context, CL_MEM_WRITE_ONLY, pixels * sizeof(cl_float));
    cl::Buffer coverage(context, CL_MEM_WRITE_ONLY, pixels * sizeof(cl_uchar));
    cl::Buffer secondary_rays(context, CL_MEM_WRITE_ONLY, pixels * sizeof(cl_uint));
    stats.memory_bytes = device_scene->bytes() + tile_pixels * spp * sizeof(cl_uint4) +
                         pixels * (sizeof(cl_float) + sizeof(cl_uchar) + sizeof(cl_uint));

    cl::Kernel camera_kernel(built.program, "trace_camera_rays");
    cl_uint arg = device_scene->set_args(camera_kernel);
    camera_kernel.setArg(arg++, to_float4(camera.eye));
    camera_kernel.setArg(arg++, to_float4(basis.forward));
    camera_kernel.setArg(arg++, to_float4(basis.right));
    camera_kernel.setArg(arg++, to_float4(basis.up));
    camera_kernel.setArg(arg++, film_scale);
    camera_kernel.setArg(arg++, cl_uint(width));
    camera_kernel.setArg(arg++, cl_uint(height));
    camera_kernel.setArg(arg++, cl_uint(spp));
    camera_kernel.setArg(arg++, seed);
    const cl_uint camera_tile_arg = arg;
    camera_kernel.setArg(arg + 2, camera_hits);

    cl::Kernel ao_kernel(built.program, settings.estimator == Estimator::Branching ? "ao_branching" : "ao_path");
    arg = device_scene->set_args(ao_kernel);
    ao_kernel.setArg(arg++, to_float4(camera.eye));
    ao_kernel.setArg(arg++, cl_uint(spp));
    ao_kernel.setArg(arg++, cl_uint(settings.bounces));
    ao_kernel.setArg(arg++, cl_uint(settings.samples));
    ao_kernel.setArg(arg++, settings.rho);
    ao_kernel.setArg(arg++, settings.max_distance);
    ao_kernel.setArg(arg++, seed);
    const cl_uint ao_tile_arg = arg;
    ao_kernel.setArg(arg + 2, camera_hits);
    ao_kernel.setArg(arg + 3, ao);
    ao_kernel.setArg(arg + 4, coverage);
    ao_kernel.setArg(arg + 5, secondary_rays);

    const std::size_t camera_group = work_group_size_for(camera_kernel, device().device, settings.work_group_size);
    const std::size_t ao_group = work_group_size_for(ao_kernel, device().device, settings.work_group_size);
    const auto enqueue_tile = [&](std::size_t first, std::size_t count) {
      for (auto [kernel, tile_arg] : {std::pair{&camera_kernel, camera_tile_arg}, std::pair{&ao_kernel, ao_tile_arg}}) {
        kernel->setArg(tile_arg, cl_uint(first));
        kernel->setArg(tile_arg + 1, cl_uint(count));
      }
      launch(queue, camera_kernel, count * spp, camera_group);
      launch(queue, ao_kernel, count, ao_group);
    };
    // Some drivers (PoCL) compile a kernel for its work-group size at its first
    // launch: do that in an empty launch, counted as kernel build time.
    if (warmed_up_.insert({built.program(), to_string(settings.estimator), camera_group, ao_group}).second) {
      Stopwatch warm_up_clock;
      enqueue_tile(0, 0);
      queue.finish();
      stats.kernel_build_ms += warm_up_clock.elapsed_ms();
    }

    Stopwatch frame_clock;
    for (std::size_t first = 0; first < pixels; first += tile_pixels) {
      enqueue_tile(first, std::min(tile_pixels, pixels - first));
      ++stats.tiles;
    }
    queue.enqueueReadBuffer(ao, CL_FALSE, 0, pixels * sizeof(cl_float), result.ao.data());
    queue.enqueueReadBuffer(coverage, CL_FALSE, 0, pixels * sizeof(cl_uchar), result.mask.data());
    queue.enqueueReadBuffer(secondary_rays, CL_FALSE, 0, pixels * sizeof(cl_uint), rays.data());
    queue.finish();
    stats.frame_ms = frame_clock.elapsed_ms();
  } catch (const cl::Error& e) {
    throw_device_error("rendering " + scene->name() + " on " + device().description(), e);
  }

  stats.rays_primary = std::uint64_t(pixels) * spp;
  for (cl_uint r : rays) stats.rays_secondary += r;
  return result;
}

std::vector<RayHit> Renderer::trace(const std::shared_ptr<const Scene>& scene, const std::vector<cl_float4>& origins,
                                    const std::vector<cl_float4>& directions, bool any_hit, Traversal traversal) {
  if (origins.size() != directions.size())
    throw std::invalid_argument("trace: " + std::to_string(origins.size()) + " origins but " +
                                std::to_string(directions.size()) + " directions");
  std::vector<RayHit> hits(origins.size());
  if (origins.empty()) return hits;
  std::lock_guard<std::mutex> lock(mutex_);
  const std::shared_ptr<const DeviceScene> device_scene = scenes_.get(*compute_, scene, false);
  const BuiltProgram built = compute_->programs().get("trace.cl", program_options(traversal));
  static_assert(sizeof(RayHit) == sizeof(cl_uint4), "RayHit mirrors the kernel's uint4 hit record");
  try {
    const cl::Context& context = compute_->context();
    cl::CommandQueue& queue = compute_->queue();
    const std::size_t n = origins.size();
    cl::Buffer origin_buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float4),
                             const_cast<cl_float4*>(origins.data()));
    cl::Buffer direction_buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float4),
                                const_cast<cl_float4*>(directions.data()));
    cl::Buffer hit_buffer(context, CL_MEM_WRITE_ONLY, n * sizeof(cl_uint4));
    cl::Kernel kernel(built.program, "trace_rays");
    cl_uint arg = device_scene->set_args(kernel);
    kernel.setArg(arg++, origin_buffer);
    kernel.setArg(arg++, direction_buffer);
    kernel.setArg(arg++, cl_uint(n));
    kernel.setArg(arg++, cl_int(any_hit));
    kernel.setArg(arg++, hit_buffer);
    launch(queue, kernel, n, work_group_size_for(kernel, device().device, 0));
    queue.enqueueReadBuffer(hit_buffer, CL_TRUE, 0, n * sizeof(cl_uint4), hits.data());
  } catch (const cl::Error& e) {
    throw_device_error("tracing rays in " + scene->name() + " on " + device().description(), e);
  }
  return hits;
}

}  // namespace mbao
