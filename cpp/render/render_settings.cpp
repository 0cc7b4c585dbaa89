#include "render/render_settings.h"

#include <cmath>
#include <stdexcept>

namespace mbao {
namespace {

[[noreturn]] void bad(const std::string& message) { throw std::invalid_argument(message); }

void check_range(const char* name, std::int64_t value, std::int64_t lo, std::int64_t hi) {
  if (value < lo || value > hi)
    bad(std::string(name) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
        std::to_string(value));
}

// Past this a pixel's ray count would not fit the 32-bit counter the kernels keep.
constexpr std::uint64_t kMaxRaysPerPixel = 0xFFFFFFFFull;

}  // namespace

Estimator parse_estimator(const std::string& name) {
  if (name == "branching") return Estimator::Branching;
  if (name == "path") return Estimator::Path;
  bad("estimator must be \"branching\" or \"path\", got \"" + name + "\"");
}

NormalMode parse_normal_mode(const std::string& name) {
  if (name == "shading") return NormalMode::Shading;
  if (name == "geometric") return NormalMode::Geometric;
  bad("normals must be \"shading\" or \"geometric\", got \"" + name + "\"");
}

Traversal parse_traversal(const std::string& name) {
  if (name == "pushdown") return Traversal::PushDown;
  if (name == "restart") return Traversal::Restart;
  if (name == "short-stack") return Traversal::ShortStack;
  if (name == "stack") return Traversal::Stack;
  if (name == "lanes") return Traversal::Lanes;
  if (name == "auto") return Traversal::Auto;
  bad("traversal must be \"auto\", \"pushdown\", \"restart\", \"short-stack\", \"stack\" or \"lanes\", got \"" +
      name + "\"");
}

KernelOrganisation parse_organisation(const std::string& name) {
  if (name == "megakernel") return KernelOrganisation::Megakernel;
  if (name == "wavefront") return KernelOrganisation::Wavefront;
  if (name == "auto") return KernelOrganisation::Auto;
  bad("organisation must be \"auto\", \"megakernel\" or \"wavefront\", got \"" + name + "\"");
}

Method parse_method(const std::string& name) {
  if (name == "raytraced") return Method::RayTraced;
  if (name == "hbao") return Method::Hbao;
  bad("method must be \"raytraced\" or \"hbao\", got \"" + name + "\"");
}

std::string to_string(Method method) { return method == Method::RayTraced ? "raytraced" : "hbao"; }

std::string to_string(Estimator estimator) { return estimator == Estimator::Branching ? "branching" : "path"; }
std::string to_string(NormalMode mode) { return mode == NormalMode::Shading ? "shading" : "geometric"; }
std::string to_string(Traversal traversal) {
  switch (traversal) {
    case Traversal::Restart: return "restart";
    case Traversal::PushDown: return "pushdown";
    case Traversal::ShortStack: return "short-stack";
    case Traversal::Stack: return "stack";
    case Traversal::Lanes: return "lanes";
    default: return "auto";
  }
}

std::string to_string(KernelOrganisation organisation) {
  switch (organisation) {
    case KernelOrganisation::Megakernel: return "megakernel";
    case KernelOrganisation::Wavefront: return "wavefront";
    default: return "auto";
  }
}

std::uint64_t RenderSettings::max_rays_per_camera_sample() const {
  if (estimator == Estimator::Path) return std::uint64_t(samples) * std::uint64_t(bounces);
  std::uint64_t total = 0, level = 1;
  for (std::int64_t k = 0; k < bounces; ++k) {
    level *= std::uint64_t(samples);
    total += level;
    if (total > kMaxRaysPerPixel) return total;  // stop before it can overflow
  }
  return total;
}

std::uint64_t RenderSettings::max_rays_in_total() const {
  const std::uint64_t camera_samples = std::uint64_t(width) * std::uint64_t(height) * std::uint64_t(spp);
  const std::uint64_t per_sample = 1 + max_rays_per_camera_sample();
  if (per_sample > std::numeric_limits<std::uint64_t>::max() / camera_samples)
    return std::numeric_limits<std::uint64_t>::max();
  return camera_samples * per_sample;
}

std::uint64_t RenderSettings::max_queue_entries_per_camera_sample() const {
  std::uint64_t deepest = 0, second = 0, level = 1;
  for (std::int64_t k = 1; k < bounces; ++k) {
    level *= std::uint64_t(samples);
    second = deepest;
    deepest = level;
    if (deepest > kMaxRaysPerPixel) break;  // stop before it can overflow
  }
  return deepest + second;
}

bool RenderSettings::wavefront_can_run() const {
  return method == Method::RayTraced && estimator == Estimator::Branching &&
         max_queue_entries_per_camera_sample() * std::uint64_t(spp) <= kMaxWavefrontQueueEntries;
}

void RenderSettings::validate() const {
  check_range("width", width, 1, 16384);
  check_range("height", height, 1, 16384);
  check_range("samples", samples, 1, 1 << 20);
  check_range("spp", spp, 1, 1 << 16);
  check_range("bounces", bounces, 1, estimator == Estimator::Branching ? kMaxBranchingBounces : 1 << 16);
  if (!(rho >= 0.0f && rho <= 1.0f)) bad("rho must be in [0, 1], got " + std::to_string(rho));
  if (!(max_distance > 0.0f)) bad("max_distance must be > 0 (inf for unlimited), got " + std::to_string(max_distance));
  if (method == Method::Hbao) return validate_hbao();
  const std::uint64_t per_pixel = max_rays_per_camera_sample() * std::uint64_t(spp);
  if (per_pixel > kMaxRaysPerPixel) {
    std::string message = "the " + to_string(estimator) + " estimator with samples=" + std::to_string(samples) +
                          ", bounces=" + std::to_string(bounces) + " and spp=" + std::to_string(spp) +
                          " traces more than " + std::to_string(kMaxRaysPerPixel) + " rays per pixel";
    if (estimator == Estimator::Branching)
      message += "; the path estimator needs at most samples * bounces = " +
                 std::to_string(std::uint64_t(samples) * std::uint64_t(bounces)) + " per camera sample";
    bad(message);
  }
  validate_work();
  if (organisation == KernelOrganisation::Wavefront) validate_wavefront();
  if (traversal == Traversal::Lanes) validate_lanes();
}

void RenderSettings::validate_hbao() const {
  if (bounces != 1)
    bad("HBAO computes one bounce, got bounces=" + std::to_string(bounces) +
        "; mbao.gtao_multibounce approximates more from its image");
  if (spp != 1) bad("HBAO samples each pixel at its centre, got spp=" + std::to_string(spp));
  if (!std::isfinite(max_distance))
    bad("HBAO needs a finite max_distance: it is the radius, in world units, that it searches for occluders");
  if (organisation == KernelOrganisation::Wavefront) bad("organisation \"wavefront\" applies to the ray-traced method only");
  check_range("hbao directions", hbao.directions, 1, 64);
  check_range("hbao steps", hbao.steps, 1, 64);
  if (!(hbao.angle_bias_deg >= 0.0f && hbao.angle_bias_deg < 90.0f))
    bad("hbao angle_bias_deg must be in [0, 90), got " + std::to_string(hbao.angle_bias_deg));
  if (!(hbao.falloff >= 0.0f && hbao.falloff <= 1.0f))
    bad("hbao falloff must be in [0, 1], got " + std::to_string(hbao.falloff));
}

void RenderSettings::validate_work() const {
  const std::uint64_t rays = max_rays_in_total();
  if (rays <= max_rays) return;
  const std::uint64_t camera_samples = std::uint64_t(width) * std::uint64_t(height) * std::uint64_t(spp);
  std::string message = "this render would trace up to " + std::to_string(rays) + " rays (" +
                        std::to_string(camera_samples) + " camera samples x " +
                        std::to_string(1 + max_rays_per_camera_sample()) + " rays each), more than max_rays=" +
                        std::to_string(max_rays);
  if (estimator == Estimator::Branching)
    message += "; the branching estimator traces samples^1 + ... + samples^bounces rays per camera sample, "
               "the path estimator samples * bounces = " + std::to_string(std::uint64_t(samples) * std::uint64_t(bounces)) +
               " (estimator=\"path\")";
  bad(message + "; raise max_rays to run it anyway");
}

void RenderSettings::validate_lanes() const {
  if (organisation == KernelOrganisation::Megakernel)
    bad("traversal \"lanes\" walks a bounce's rays together, so it runs in organisation \"wavefront\" (or \"auto\"), "
        "not \"megakernel\"");
  if (origin_paths.value_or(false))
    bad("origin_paths applies to the walks of one ray per work item; traversal \"lanes\" starts every ray at the root");
  if (estimator != Estimator::Branching)
    bad("traversal \"lanes\" runs in the wavefront organisation, which runs the branching estimator only; the path "
        "estimator needs another traversal");
  validate_wavefront();
}

void RenderSettings::validate_wavefront() const {
  if (estimator != Estimator::Branching)
    bad("the wavefront organisation runs the branching estimator only; the path estimator needs "
        "organisation \"megakernel\"");
  if (wavefront_can_run()) return;
  bad("the wavefront organisation with samples=" + std::to_string(samples) + ", bounces=" + std::to_string(bounces) +
      " and spp=" + std::to_string(spp) + " queues up to " +
      std::to_string(max_queue_entries_per_camera_sample() * std::uint64_t(spp)) +
      " surfaces per pixel, more than its limit of " + std::to_string(kMaxWavefrontQueueEntries) +
      "; organisation \"megakernel\" keeps one surface per bounce");
}

}  // namespace mbao
