#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "mbao/limits.h"
#include "mbao/traversal.h"

namespace mbao {

enum class Estimator { Branching, Path };
enum class NormalMode { Shading, Geometric };
// Lanes: the full stack, sixteen rays per work item (kernels/kd_lanes.h); a
// render walks its AO rays so in the wavefront organisation only, and its
// camera rays sixteen to a packet (kernels/kd_packet.h).
// Auto: the fastest measured for the device's class (plan_render in render/render_plan.h).
// The values are the kernels' MBAO_TRAVERSAL (kernels/mbao/traversal.h).
enum class Traversal {
  Restart = MBAO_TRAVERSAL_RESTART,
  PushDown = MBAO_TRAVERSAL_PUSHDOWN,
  ShortStack = MBAO_TRAVERSAL_SHORT_STACK,
  Stack = MBAO_TRAVERSAL_STACK,
  Lanes = MBAO_TRAVERSAL_LANES,
  Auto
};
// How the AO work is cut into kernels: one work item per pixel runs the whole
// estimator, or one launch per bounce over a queue of the surfaces that bounce on.
// Auto: the faster measured for the device's type where the wavefront can run
// the settings (plan_render in render/render_plan.h).
enum class KernelOrganisation { Megakernel, Wavefront, Auto };
// What computes the image: the ray-traced estimators of SPEC 2, or HBAO (SPEC 4).
enum class Method { RayTraced, Hbao };

// HBAO's own settings; its radius is the render's max_distance.
struct HbaoSettings {
  std::int64_t directions = 8;   // image directions per pixel, rotated per pixel
  std::int64_t steps = 6;        // samples along each direction
  float angle_bias_deg = 10.0f;  // horizons less than this above the tangent plane are ignored
  float falloff = 1.0f;          // attenuation W(r) = 1 - falloff * (r / radius)^2, in [0, 1]
  // Throws std::invalid_argument naming the first setting out of its range.
  void validate() const;
};

// The spatial filter's settings, with SPEC 7.3's defaults.
struct DenoiseSettings {
  std::int64_t iterations = 5;      // K; iteration i takes taps 2^i pixels apart
  float sigma_plane = 1.0f;         // distance from the tangent plane, in footprints
  std::int64_t sigma_normal = 128;  // the exponent on the normals' cosine
  float sigma_value = 4.0f;         // value differences, in standard deviations of the blurred variance
  // Throws std::invalid_argument naming the first setting out of its range.
  void validate() const;
};

// Temporal accumulation's settings (SPEC 7.4), with its default.
struct TemporalSettings {
  std::int64_t max_length = 64;  // N, the history length a pixel's mean is capped at
  // Throws std::invalid_argument where max_length is out of its range.
  void validate() const;
};

// Names as the Python API spells them; parse_* throw std::invalid_argument
// listing the allowed names.
Estimator parse_estimator(const std::string& name);
NormalMode parse_normal_mode(const std::string& name);
Traversal parse_traversal(const std::string& name);
KernelOrganisation parse_organisation(const std::string& name);
Method parse_method(const std::string& name);
std::string to_string(Estimator estimator);
std::string to_string(NormalMode mode);
std::string to_string(Traversal traversal);
std::string to_string(KernelOrganisation organisation);
std::string to_string(Method method);
// Every name parse_* takes for enum E, in the order its errors list them.
template <typename E>
std::vector<std::string> names_of();

// About a quarter of an hour on two CPU cores under PoCL (~10 M rays/s), ten
// seconds on a GPU: past this a render is more likely a mistake (r^b grows
// fast) than a plan, and the caller says so by raising max_rays.
constexpr std::uint64_t kDefaultMaxRays = 10'000'000'000ull;

// Everything a render is asked for besides the scene and the camera (SPEC 1-2).
struct RenderSettings {
  // 64-bit so that any integer a caller passes reaches validate() unchanged.
  std::int64_t width = 512;
  std::int64_t height = 512;
  std::int64_t bounces = 1;
  std::int64_t samples = 4;  // r: directions per hit
  Estimator estimator = Estimator::Branching;
  float rho = 1.0f;
  // Unset: the camera's suggested radius where it has one, else inf (SPEC 1);
  // Renderer::render sets it so before anything reads radius().
  std::optional<float> max_distance;
  std::int64_t spp = 1;
  NormalMode normals = NormalMode::Shading;
  std::uint64_t seed = 0;
  Traversal traversal = Traversal::Auto;
  bool traversal_stats = false;  // build the kernels that count nodes, leaves, triangle tests and restarts
  bool variance = false;         // estimate each pixel's variance (SPEC 7.1) into RenderResult::variance
  // How the work is cut up; none of these changes the image.
  std::size_t tile_pixels = 0;      // pixels per launch; 0 picks a size that bounds memory (the wavefront's always)
  std::size_t work_group_size = 0;  // 0 lets the OpenCL driver choose
  KernelOrganisation organisation = KernelOrganisation::Auto;  // wavefront: branching estimator only
  // Whether the rays that leave one surface point walk its path down the kd-tree
  // from private memory (OriginPath in kernels/kd_traversal.h); unset: the
  // the plan's choice (plan_render in render/render_plan.h).
  std::optional<bool> origin_paths;
  Method method = Method::RayTraced;
  HbaoSettings hbao;                       // method Hbao only
  std::optional<DenoiseSettings> denoise;  // the spatial filter after the AO (SPEC 7.3); unset: none
  // A frame of a sequence that accumulates (SPEC 7.4), before any spatial filter; unset: none.
  std::optional<TemporalSettings> temporal;
  // Renders that could trace more rays than this are refused before they start.
  std::uint64_t max_rays = kDefaultMaxRays;

  // The AO radius: max_distance, inf where unset.
  float radius() const { return max_distance.value_or(std::numeric_limits<float>::infinity()); }
  // Throws std::invalid_argument naming the first bad setting and its allowed range.
  void validate() const;
  // Upper bound on the AO rays of one camera sample: r + ... + r^b or r * b.
  std::uint64_t max_rays_per_camera_sample() const;
  // Upper bound on all the rays of the render, camera rays included (saturates at 2^64 - 1).
  std::uint64_t max_rays_in_total() const;
  // Upper bound on the wavefront queue entries of one camera sample: the
  // surfaces of the two deepest bounces that bounce on, r^(b-1) + r^(b-2)
  // (a bounce reads one queue and fills the other).
  std::uint64_t max_queue_entries_per_camera_sample() const;
  // Whether the kernels keep the moments of the directions drawn at each primary
  // hit: for a variance at spp = 1 (SPEC 7.1).
  bool direction_moments() const { return (variance || filtered()) && spp == 1 && method == Method::RayTraced; }
  // Whether screen-space passes follow the AO, which read its G-buffer and
  // variance (SPEC 7.2-7.4): denoising or temporal accumulation.
  bool filtered() const { return denoise || temporal; }
  // Whether the wavefront organisation can run these settings: the ray-traced
  // branching estimator, with a pixel's queue entries within kMaxWavefrontQueueEntries.
  bool wavefront_can_run() const;

 private:
  void validate_wavefront() const;
  void validate_lanes() const;
  void validate_work() const;
  void validate_hbao() const;
  void validate_filters() const;
};

// The largest bounce count of the branching estimator; the path estimator has no such limit.
constexpr std::int64_t kMaxBranchingBounces = MBAO_MAX_BRANCHING_BOUNCES;

// The most wavefront queue entries a tile holds (64 MiB of 32-byte entries):
// tiles are made small enough, and settings whose single pixel needs more are refused.
constexpr std::uint64_t kMaxWavefrontQueueEntries = std::uint64_t(1) << 21;

}  // namespace mbao
