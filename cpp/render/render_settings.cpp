#include "render/render_settings.h"

#include <cmath>
#include <stdexcept>

#include "render/setting_specs.h"

namespace mbao {
namespace {

[[noreturn]] void bad(const std::string& message) { throw std::invalid_argument(message); }

// Every setting of `settings` checked against its table, the errors naming `what` it is.
template <typename Settings>
void check_all(const Settings& settings, const std::vector<SettingSpecOf<Settings>>& specs, const std::string& what) {
  for (const SettingSpecOf<Settings>& spec : specs)
    spec.SettingRange::check(what + " " + spec.name, spec.get(settings));
}

// Past this a pixel's ray count would not fit the 32-bit counter the kernels keep.
constexpr std::uint64_t kMaxRaysPerPixel = 0xFFFFFFFFull;

}  // namespace

namespace {

// Each choice's values by the names the Python API gives them, in the order its errors list them.
template <typename E>
struct Named {
  const char* name;
  E value;
};
const Named<Estimator> kEstimators[] = {{"branching", Estimator::Branching}, {"path", Estimator::Path}};
const Named<NormalMode> kNormalModes[] = {{"shading", NormalMode::Shading}, {"geometric", NormalMode::Geometric}};
const Named<Traversal> kTraversals[] = {{"auto", Traversal::Auto},       {"pushdown", Traversal::PushDown},
                                        {"restart", Traversal::Restart}, {"short-stack", Traversal::ShortStack},
                                        {"stack", Traversal::Stack},     {"lanes", Traversal::Lanes}};
const Named<KernelOrganisation> kOrganisations[] = {{"auto", KernelOrganisation::Auto},
                                                    {"megakernel", KernelOrganisation::Megakernel},
                                                    {"wavefront", KernelOrganisation::Wavefront}};
const Named<Method> kMethods[] = {{"raytraced", Method::RayTraced}, {"hbao", Method::Hbao}};

template <typename E, std::size_t N>
E parse(const char* setting, const Named<E> (&names)[N], const std::string& name) {
  std::string allowed;
  for (std::size_t i = 0; i < N; ++i) {
    if (name == names[i].name) return names[i].value;
    allowed += (i == 0 ? "\"" : i + 1 < N ? ", \"" : " or \"") + std::string(names[i].name) + "\"";
  }
  bad(std::string(setting) + " must be " + allowed + ", got \"" + name + "\"");
}

template <typename E, std::size_t N>
std::string name_of(const Named<E> (&names)[N], E value) {
  for (const Named<E>& named : names)
    if (named.value == value) return named.name;
  return "?";
}

template <typename E, std::size_t N>
std::vector<std::string> all_names(const Named<E> (&names)[N]) {
  std::vector<std::string> all;
  for (const Named<E>& named : names) all.push_back(named.name);
  return all;
}

}  // namespace

Estimator parse_estimator(const std::string& name) { return parse("estimator", kEstimators, name); }
NormalMode parse_normal_mode(const std::string& name) { return parse("normals", kNormalModes, name); }
Traversal parse_traversal(const std::string& name) { return parse("traversal", kTraversals, name); }
KernelOrganisation parse_organisation(const std::string& name) { return parse("organisation", kOrganisations, name); }
Method parse_method(const std::string& name) { return parse("method", kMethods, name); }

std::string to_string(Estimator estimator) { return name_of(kEstimators, estimator); }
std::string to_string(NormalMode mode) { return name_of(kNormalModes, mode); }
std::string to_string(Traversal traversal) { return name_of(kTraversals, traversal); }
std::string to_string(KernelOrganisation organisation) { return name_of(kOrganisations, organisation); }
std::string to_string(Method method) { return name_of(kMethods, method); }

template <>
std::vector<std::string> names_of<Estimator>() {
  return all_names(kEstimators);
}
template <>
std::vector<std::string> names_of<NormalMode>() {
  return all_names(kNormalModes);
}
template <>
std::vector<std::string> names_of<Traversal>() {
  return all_names(kTraversals);
}
template <>
std::vector<std::string> names_of<KernelOrganisation>() {
  return all_names(kOrganisations);
}
template <>
std::vector<std::string> names_of<Method>() {
  return all_names(kMethods);
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
  if (estimator == Estimator::Branching && (bounces < 1 || bounces > kMaxBranchingBounces))
    bad("bounces must be in [1, " + std::to_string(kMaxBranchingBounces) + "] for the branching estimator, got " +
        std::to_string(bounces) +
        (bounces > 1 ? "; the path estimator takes up to " +
                           std::to_string(std::get<std::int64_t>(setting_spec("bounces").hi)) + " (estimator=\"path\")"
                     : ""));
  for (const SettingSpec& spec : setting_specs()) spec.check(*this);
  if (method == Method::Hbao) return validate_hbao();
  if (variance && spp == 1 && samples == 1)
    bad("variance needs two samples of a pixel to spread (SPEC 7.1): spp >= 2, or samples (r) >= 2 at spp=1; got "
        "spp=1, samples=1");
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
  if (filtered()) validate_filters();
  if (organisation == KernelOrganisation::Wavefront) validate_wavefront();
  if (traversal == Traversal::Lanes) validate_lanes();
}

void RenderSettings::validate_hbao() const {
  if (bounces != 1)
    bad("HBAO computes one bounce, got bounces=" + std::to_string(bounces) +
        "; mbao.gtao_multibounce approximates more from its image");
  if (spp != 1) bad("HBAO samples each pixel at its centre, got spp=" + std::to_string(spp));
  if (variance) bad("variance is the spread of a ray-traced pixel's samples (SPEC 7.1); HBAO has none");
  if (denoise) bad("denoise filters a ray-traced image by its variance (SPEC 7.3); HBAO has none");
  if (temporal) bad("temporal accumulation blends ray-traced frames by their variance (SPEC 7.4); HBAO has none");
  if (!std::isfinite(radius()))
    bad("HBAO needs a finite max_distance: it is the radius, in world units, that it searches for occluders");
  if (organisation == KernelOrganisation::Wavefront)
    bad("organisation \"wavefront\" applies to the ray-traced method only");
  hbao.validate();
}

void HbaoSettings::validate() const { check_all(*this, hbao_setting_specs(), "hbao"); }

void DenoiseSettings::validate() const { check_all(*this, denoise_setting_specs(), "denoise"); }

void TemporalSettings::validate() const { check_all(*this, temporal_setting_specs(), "temporal"); }

void RenderSettings::validate_filters() const {
  if (denoise) denoise->validate();
  if (temporal) temporal->validate();
  const std::string what = denoise ? "denoise" : "temporal accumulation";
  if (spp != 1)
    bad(what + " needs spp=1, got spp=" + std::to_string(spp) +
        ": its G-buffer is each pixel's one camera hit, "
        "through the pixel centre (SPEC 7.2)");
  if (samples < 2)
    bad(what +
        " weighs values by their variance, the spread of the r directions at each hit (SPEC 7.1): it needs "
        "samples >= 2, got samples=" +
        std::to_string(samples));
}

void RenderSettings::validate_work() const {
  const std::uint64_t rays = max_rays_in_total();
  if (rays <= max_rays) return;
  const std::uint64_t camera_samples = std::uint64_t(width) * std::uint64_t(height) * std::uint64_t(spp);
  std::string message = "this render would trace up to " + std::to_string(rays) + " rays (" +
                        std::to_string(camera_samples) + " camera samples x " +
                        std::to_string(1 + max_rays_per_camera_sample()) +
                        " rays each), more than max_rays=" + std::to_string(max_rays);
  if (estimator == Estimator::Branching)
    message +=
        "; the branching estimator traces samples^1 + ... + samples^bounces rays per camera sample, "
        "the path estimator samples * bounces = " +
        std::to_string(std::uint64_t(samples) * std::uint64_t(bounces)) + " (estimator=\"path\")";
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
