#include "render/setting_specs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "mbao/limits.h"

namespace mbao {
namespace {

constexpr std::uint64_t kMaxUnsigned = std::numeric_limits<std::uint64_t>::max();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The accessors of one member of a settings struct as a setting of kind `kind`.
template <typename Settings, typename Member>
SettingSpecOf<Settings> member(const char* name, SettingGroup group, SettingKind kind, Member Settings::*field,
                               const char* doc) {
  SettingSpecOf<Settings> spec;
  spec.name = name;
  spec.group = group;
  spec.kind = kind;
  spec.doc = doc;
  spec.get = [field, kind](const Settings& s) -> SettingValue {
    switch (kind) {
      case SettingKind::Integer: return std::int64_t(s.*field);
      case SettingKind::Unsigned:
      case SettingKind::AutoCount: return std::uint64_t(s.*field);
      case SettingKind::Real: return double(s.*field);
      default: return bool(s.*field);
    }
  };
  spec.set = [field](Settings& s, const SettingValue& value) {
    std::visit(
        [&](const auto& v) {
          using T = std::decay_t<decltype(v)>;
          if constexpr (!std::is_same_v<T, std::string> && !std::is_same_v<T, std::monostate>) s.*field = Member(v);
        },
        value);
  };
  return spec;
}

template <typename Settings>
SettingSpecOf<Settings> integer(const char* name, std::int64_t Settings::*field, std::int64_t lo, std::int64_t hi,
                                const char* doc) {
  SettingSpecOf<Settings> spec = member(name, SettingGroup::Render, SettingKind::Integer, field, doc);
  spec.lo = lo;
  spec.hi = hi;
  return spec;
}

// An unsigned 64-bit setting in [lo, 2^64).
SettingSpec whole(const char* name, std::uint64_t RenderSettings::*field, std::uint64_t lo, const char* doc) {
  SettingSpec spec = member(name, SettingGroup::Render, SettingKind::Unsigned, field, doc);
  spec.lo = lo;
  spec.hi = kMaxUnsigned;
  return spec;
}

// Which ends of a real setting's range are refused themselves.
enum class Ends { Closed, LowOpen, HighOpen, Open };

template <typename Settings>
SettingSpecOf<Settings> real(const char* name, float Settings::*field, double lo, double hi, Ends ends,
                             const char* doc) {
  SettingSpecOf<Settings> spec = member(name, SettingGroup::Render, SettingKind::Real, field, doc);
  spec.lo = lo;
  spec.hi = hi;
  spec.lo_open = ends == Ends::LowOpen || ends == Ends::Open;
  spec.hi_open = ends == Ends::HighOpen || ends == Ends::Open;
  return spec;
}

// A setting that may be left unset, to stand for `none_means`; > lo.
SettingSpec optional_real(const char* name, std::optional<float> RenderSettings::*field, double lo,
                          const char* none_means, const char* doc) {
  SettingSpec spec;
  spec.name = name;
  spec.kind = SettingKind::Real;
  spec.doc = doc;
  spec.lo = lo;
  spec.lo_open = true;
  spec.hi = kInf;
  spec.none_means = none_means;
  spec.get = [field](const RenderSettings& s) -> SettingValue {
    if (!(s.*field)) return std::monostate{};
    return double(*(s.*field));
  };
  spec.set = [field](RenderSettings& s, const SettingValue& value) {
    if (std::holds_alternative<std::monostate>(value))
      (s.*field).reset();
    else
      s.*field = float(std::get<double>(value));
  };
  return spec;
}

// An enum member, set and read by the names parse and to_string give its values.
template <typename Settings, typename E>
SettingSpecOf<Settings> choice(const char* name, SettingGroup group, E Settings::*field, E (*parse)(const std::string&),
                               const char* doc) {
  SettingSpecOf<Settings> spec;
  spec.name = name;
  spec.group = group;
  spec.kind = SettingKind::Choice;
  spec.doc = doc;
  spec.choices = names_of<E>();
  spec.get = [field](const Settings& s) -> SettingValue { return to_string(s.*field); };
  spec.set = [field, parse](Settings& s, const SettingValue& value) { s.*field = parse(std::get<std::string>(value)); };
  return spec;
}

// A string member that holds one of `choices`.
template <typename Settings>
SettingSpecOf<Settings> named(const char* name, std::string Settings::*field, std::vector<std::string> choices,
                              const char* doc) {
  SettingSpecOf<Settings> spec;
  spec.name = name;
  spec.kind = SettingKind::Choice;
  spec.doc = doc;
  spec.choices = std::move(choices);
  spec.get = [field](const Settings& s) -> SettingValue { return s.*field; };
  spec.set = [field, name = spec.name, allowed = spec.choices, range = spec.range()](Settings& s,
                                                                                     const SettingValue& value) {
    const std::string& given = std::get<std::string>(value);
    if (std::find(allowed.begin(), allowed.end(), given) == allowed.end())
      throw std::invalid_argument(name + " must be " + range + ", got \"" + given + "\"");
    s.*field = given;
  };
  return spec;
}

// r, the directions drawn at a point: a render's samples, a bake's directions.
constexpr std::int64_t kMaxDirections = std::int64_t(1) << 20;

std::vector<SettingSpec> make_specs() {
  using G = SettingGroup;
  using K = SettingKind;
  return {
      integer("width", &RenderSettings::width, 1, 16384, "Image width in pixels."),
      integer("height", &RenderSettings::height, 1, 16384, "Image height in pixels."),
      integer("bounces", &RenderSettings::bounces, 1, 1 << 16,
              "b, the bounces of SPEC 1; the branching estimator takes at most 16."),
      integer("samples", &RenderSettings::samples, 1, kMaxDirections, "r, the directions drawn at each hit."),
      choice("estimator", G::Render, &RenderSettings::estimator, parse_estimator,
             "\"branching\" (the paper's: r + r^2 + ... + r^b rays per camera sample) or \"path\" (r paths of up "
             "to b segments, r * b rays); the same expectation (SPEC 2)."),
      real("rho", &RenderSettings::rho, 0.0, 1.0, Ends::Closed, "The albedo of every surface."),
      optional_real("max_distance", &RenderSettings::max_distance, 0.0,
                    "the camera's max_distance where it suggests one (camera.json, a glTF camera's extras), else "
                    "inf; for HBAO then a quarter of the scene's diagonal",
                    "The AO radius: hits farther away count as misses; inf for none (SPEC 1). HBAO's search "
                    "radius."),
      integer("spp", &RenderSettings::spp, 1, 1 << 16,
              "Camera samples per pixel: 1 through the pixel centre, more jittered in the pixel (a box filter)."),
      choice("normals", G::Render, &RenderSettings::normals, parse_normal_mode,
             "\"shading\" (interpolated vertex normals where the mesh has them) or \"geometric\" (SPEC 3.3)."),
      whole("seed", &RenderSettings::seed, 0,
            "The image is a function of the seed and the render settings alone, whatever the device or engine."),
      choice("method", G::Render, &RenderSettings::method, parse_method,
             "\"raytraced\" (the estimators) or \"hbao\": screen-space horizon-based AO (SPEC 4) on the camera "
             "rays' hits through the pixel centres, with radius max_distance, one bounce and spp 1."),
      member<RenderSettings>(
          "variance", G::Render, K::Flag, &RenderSettings::variance,
          "Estimate each pixel's variance from the spread of its samples (SPEC 7.1) into Result.variance: "
          "its camera samples' at spp >= 2, else its r directions' (samples >= 2)."),
      whole("max_rays", &RenderSettings::max_rays, 1,
            "A render that could trace more rays than this, camera rays included, is refused before it starts."),
      choice("traversal", G::Engine, &RenderSettings::traversal, parse_traversal,
             "How rays walk the kd-tree: \"pushdown\" or \"short-stack\" (Horn et al. 2007), \"restart\" (Foley "
             "and Sugerman 2005), \"stack\" (a full stack), \"lanes\" (the full stack, sixteen rays per work item; "
             "the branching estimator in the wavefront only) or \"auto\": the device's choice "
             "(docs/kernel-variants.md)."),
      choice("organisation", G::Engine, &RenderSettings::organisation, parse_organisation,
             "\"megakernel\" (a work item runs a pixel's estimator), \"wavefront\" (branching only: a launch per "
             "bounce over a queue of the surfaces that bounce on) or \"auto\": the device's choice."),
      member<RenderSettings>("tile_pixels", G::Engine, K::AutoCount, &RenderSettings::tile_pixels,
                             "Pixels per launch; automatic bounds the memory and the rays of a launch."),
      member<RenderSettings>("work_group_size", G::Engine, K::AutoCount, &RenderSettings::work_group_size,
                             "OpenCL work-group size; automatic is 64, or the kernel's limit where lower."),
      member<RenderSettings>(
          "traversal_stats", G::Engine, K::Flag, &RenderSettings::traversal_stats,
          "Count nodes, leaves, triangle tests and restarts per ray into stats[\"traversal\"] (kernels "
          "built to count, somewhat slower)."),
  };
}

std::vector<SettingSpecOf<HbaoSettings>> make_hbao_specs() {
  using H = HbaoSettings;
  return {
      integer("directions", &H::directions, 1, 64,
              "Image directions marched from each pixel, rotated per pixel by "
              "the seed."),
      integer("steps", &H::steps, 1, 64, "Samples along each direction, the first one jittered per pixel."),
      real("angle_bias_deg", &H::angle_bias_deg, 0.0, 90.0, Ends::HighOpen,
           "Horizons less than this many degrees above the tangent plane are ignored."),
      real("falloff", &H::falloff, 0.0, 1.0, Ends::Closed,
           "The attenuation W(r) = 1 - falloff * (r / radius)^2 of each horizon rise; the radius is the render's "
           "max_distance."),
  };
}

constexpr std::int64_t kMaxIterations = 14;  // taps 2^13 pixels apart: past the widest image
constexpr std::int64_t kMaxNormalExponent = MBAO_MAX_NORMAL_EXPONENT;
static_assert(kMaxNormalExponent < (1 << MBAO_NORMAL_EXPONENT_BITS), "denoise.cl squares over these bits");

std::vector<SettingSpecOf<DenoiseSettings>> make_denoise_specs() {
  using D = DenoiseSettings;
  return {
      integer("iterations", &D::iterations, 1, kMaxIterations, "K; iteration i takes taps 2^i pixels apart."),
      real("sigma_plane", &D::sigma_plane, 0.0, kInf, Ends::Open,
           "How far, in pixel footprints, a tap may lie off the pixel's tangent plane."),
      integer("sigma_normal", &D::sigma_normal, 0, kMaxNormalExponent,
              "The exponent on the cosine between the normals; 0 ignores them."),
      real("sigma_value", &D::sigma_value, 0.0, kInf, Ends::Open,
           "How far a tap's value may differ, in standard deviations of the pixel's blurred variance."),
  };
}

std::vector<SettingSpecOf<BakeSettings>> make_bake_specs() {
  using B = BakeSettings;
  return {
      named("target", &B::target, {"vertices", "texture"},
            "\"vertices\": a value per vertex (SPEC 6.2); \"texture\": a texture per material, into a UV set "
            "(SPEC 6.3)."),
      integer("samples", &B::samples, kMinBakeSamples, kMaxBakeSamples,
              "Estimates per vertex or texel, each at its own point of the vertex's one-ring or the texel's "
              "surface; the standard error needs two."),
      choice("estimator", SettingGroup::Render, &B::estimator, parse_estimator,
             "How each estimate traces from its point (SPEC 2): \"path\" (r paths of b segments) or "
             "\"branching\" (r directions at every hit)."),
      integer("directions", &B::directions, 1, kMaxDirections,
              "r, the directions drawn at the point (and at every hit of the branching estimator)."),
      integer("padding", &B::padding, 0, kMaxPadding,
              "Texture only: empty texels within this many texels of a covered one take its value (dilation)."),
  };
}

constexpr std::int64_t kMaxHistoryLength = 1 << 16;  // N: from no history to one that weighs a new frame by 2^-16

std::vector<SettingSpecOf<TemporalSettings>> make_temporal_specs() {
  return {
      integer("max_length", &TemporalSettings::max_length, 1, kMaxHistoryLength,
              "N: a still camera averages its first N frames exactly, then keeps an exponential mean that weighs "
              "each new frame by 1/N; 1 keeps no history."),
  };
}

std::string number(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string value_text(const SettingValue& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>)
          return "unset";
        else if constexpr (std::is_same_v<T, std::string>)
          return "\"" + v + "\"";
        else if constexpr (std::is_same_v<T, bool>)
          return v ? "true" : "false";
        else if constexpr (std::is_same_v<T, double>)
          return std::to_string(v);
        else
          return std::to_string(v);
      },
      value);
}

}  // namespace

std::string SettingRange::range() const {
  switch (kind) {
    case SettingKind::Integer:
      return "[" + std::to_string(std::get<std::int64_t>(lo)) + ", " + std::to_string(std::get<std::int64_t>(hi)) + "]";
    case SettingKind::Unsigned: {
      const std::uint64_t top = std::get<std::uint64_t>(hi);
      return "[" + std::to_string(std::get<std::uint64_t>(lo)) + ", " +
             (top == kMaxUnsigned ? "2^64)" : std::to_string(top) + "]");
    }
    case SettingKind::AutoCount: return ">= 1, or automatic";
    case SettingKind::Real: {
      const double low = std::get<double>(lo), high = std::get<double>(hi);
      if (std::isinf(high) && !hi_open) return (lo_open ? "> " : ">= ") + number(low);
      return (lo_open ? "(" : "[") + number(low) + ", " + number(high) + (hi_open ? ")" : "]");
    }
    case SettingKind::Choice: {
      std::string text;
      for (std::size_t i = 0; i < choices.size(); ++i)
        text += (i == 0 ? "\"" : i + 1 < choices.size() ? ", \"" : " or \"") + choices[i] + "\"";
      return text;
    }
    case SettingKind::Flag: return "true or false";
  }
  return "";
}

void SettingRange::check(const std::string& name, const SettingValue& value) const {
  if (std::holds_alternative<std::monostate>(value)) return;  // unset: stands for none_means
  bool inside = true;
  switch (kind) {
    case SettingKind::Integer: {
      const std::int64_t v = std::get<std::int64_t>(value);
      inside = v >= std::get<std::int64_t>(lo) && v <= std::get<std::int64_t>(hi);
      break;
    }
    case SettingKind::Unsigned: {
      const std::uint64_t v = std::get<std::uint64_t>(value);
      inside = v >= std::get<std::uint64_t>(lo) && v <= std::get<std::uint64_t>(hi);
      break;
    }
    case SettingKind::Real: {
      const double v = std::get<double>(value), low = std::get<double>(lo);
      const double high = std::get<double>(hi);
      inside = (lo_open ? v > low : v >= low) && (hi_open ? v < high : v <= high);  // NaN is outside
      break;
    }
    default: break;  // counts, names and flags hold only allowed values once set
  }
  if (inside) return;
  const std::string where = range();
  throw std::invalid_argument(name + " must be " + (where[0] == '[' || where[0] == '(' ? "in " : "") + where +
                              ", got " + value_text(value));
}

const std::vector<SettingSpec>& setting_specs() {
  static const std::vector<SettingSpec> specs = make_specs();
  return specs;
}

const SettingSpec& setting_spec(const std::string& name) { return setting_spec_in(setting_specs(), "render", name); }

const std::vector<SettingSpecOf<HbaoSettings>>& hbao_setting_specs() {
  static const std::vector<SettingSpecOf<HbaoSettings>> specs = make_hbao_specs();
  return specs;
}

const std::vector<SettingSpecOf<DenoiseSettings>>& denoise_setting_specs() {
  static const std::vector<SettingSpecOf<DenoiseSettings>> specs = make_denoise_specs();
  return specs;
}

const std::vector<SettingSpecOf<BakeSettings>>& bake_setting_specs() {
  static const std::vector<SettingSpecOf<BakeSettings>> specs = make_bake_specs();
  return specs;
}

void BakeSettings::validate() const {
  for (const auto& spec : bake_setting_specs()) spec.check(*this);
}

const std::vector<SettingSpecOf<TemporalSettings>>& temporal_setting_specs() {
  static const std::vector<SettingSpecOf<TemporalSettings>> specs = make_temporal_specs();
  return specs;
}

}  // namespace mbao
