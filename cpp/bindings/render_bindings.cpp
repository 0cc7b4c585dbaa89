#include <iterator>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bindings/bindings.h"
#include "mbao/gbuffer.h"
#include "render/renderer.h"
#include "render/setting_specs.h"

namespace py = pybind11;

namespace mbao::bindings {
namespace {

// A setting's value as Python holds it: None for one left unset and for an automatic count.
py::object to_python(const SettingRange& spec, const SettingValue& value) {
  if (spec.kind == SettingKind::AutoCount && std::get<std::uint64_t>(value) == 0) return py::none();
  return std::visit(
      [](const auto& v) -> py::object {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          return py::none();
        else
          return py::cast(v);
      },
      value);
}

SettingValue from_python(const SettingRange& spec, const py::handle& value) {
  switch (spec.kind) {
    case SettingKind::Integer: return value.cast<std::int64_t>();
    case SettingKind::Unsigned: return value.cast<std::uint64_t>();
    case SettingKind::AutoCount: return value.is_none() ? std::uint64_t(0) : value.cast<std::uint64_t>();
    case SettingKind::Real: return value.is_none() ? SettingValue() : value.cast<double>();
    case SettingKind::Choice: return value.cast<std::string>();
    case SettingKind::Flag: return value.cast<bool>();
  }
  throw std::logic_error("unknown setting kind");
}

// A settings struct with {name: value} of its table `table` set, the rest at their defaults.
template <typename Settings>
Settings settings_of(const std::vector<SettingSpecOf<Settings>>& specs, const std::string& table,
                     const py::dict& values) {
  Settings settings;
  for (const auto& [name, value] : values) {
    const SettingSpecOf<Settings>& spec = setting_spec_in(specs, table, py::str(name));
    spec.set(settings, from_python(spec, value));
  }
  return settings;
}

}  // namespace

RenderSettings settings_from(const py::dict& values) { return settings_of(setting_specs(), "render", values); }

Renderer::TileCallback tile_callback(const py::object& progress) {
  // Ctrl-C is seen between tiles: the signal handler only sets a flag while
  // the GIL is released, so the render asks Python whether it has fired.
  return [progress](std::size_t done, std::size_t total) {
    py::gil_scoped_acquire acquire;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!progress.is_none()) progress(done, total);
  };
}

py::dict stats_dict(const RenderStats& s) {
  py::dict d;
  d["build_ms"] = s.build_ms;
  d["tree_reused"] = s.tree_reused;
  d["kernel_build_ms"] = s.kernel_build_ms;
  d["kernel_cache"] = s.kernel_cache;
  d["kernel_options"] = s.kernel_options;
  d["traversal_mode"] = s.traversal_mode;
  d["organisation"] = s.organisation.empty() ? py::object(py::none()) : py::str(s.organisation);
  d["plan"] = s.plan;
  d["kernels"] = s.kernels;
  d["max_distance"] = s.max_distance;
  d["max_distance_source"] = s.max_distance_source;
  d["upload_ms"] = s.upload_ms;
  d["frame_ms"] = s.frame_ms;
  d["gbuffer_ms"] = s.gbuffer_ms;
  d["denoise_ms"] = s.denoise_ms;
  d["temporal_ms"] = s.temporal_ms;
  d["rays_primary"] = s.rays_primary;
  d["rays_secondary"] = s.rays_secondary;
  d["memory_bytes"] = s.memory_bytes;
  d["tiles"] = s.tiles;
  d["device"] = s.device;
  d["tree"] = tree_stats_dict(s.tree);
  if (s.traversal) {
    const double rays = double(s.rays_primary + s.rays_secondary);
    py::dict traversal;
    traversal["nodes_per_ray"] = double(s.traversal->nodes) / rays;
    traversal["leaves_per_ray"] = double(s.traversal->leaves) / rays;
    traversal["triangles_per_ray"] = double(s.traversal->triangles) / rays;
    traversal["restarts_per_ray"] = double(s.traversal->restarts) / rays;
    d["traversal"] = traversal;
  }
  return d;
}

namespace {

template <typename Settings>
py::list specs_list(const std::vector<SettingSpecOf<Settings>>& table) {
  static const char* const kinds[] = {"integer", "unsigned", "auto count", "real", "choice", "flag"};
  py::list specs;
  for (const SettingSpecOf<Settings>& spec : table) {
    py::dict d;
    d["name"] = spec.name;
    d["group"] = spec.group == SettingGroup::Render ? "render" : "engine";
    d["kind"] = kinds[int(spec.kind)];
    d["doc"] = spec.doc;
    d["range"] = spec.range();
    d["none_means"] = spec.none_means.empty() ? py::object(py::none()) : py::str(spec.none_means);
    const bool numeric =
        spec.kind == SettingKind::Integer || spec.kind == SettingKind::Unsigned || spec.kind == SettingKind::Real;
    d["lo"] = numeric ? to_python(spec, spec.lo) : py::none();
    d["hi"] = numeric ? to_python(spec, spec.hi) : py::none();
    d["choices"] = spec.choices;
    d["default"] = to_python(spec, spec.default_value());
    specs.append(d);
  }
  return specs;
}

// Calls `use` with the settings table named `table`.
template <typename Use>
auto with_table(const std::string& table, Use&& use) {
  if (table == "render") return use(setting_specs());
  if (table == "hbao") return use(hbao_setting_specs());
  if (table == "denoise") return use(denoise_setting_specs());
  if (table == "temporal") return use(temporal_setting_specs());
  if (table == "bake") return use(bake_setting_specs());
  throw std::invalid_argument("no settings table \"" + table +
                              "\"; the tables are render, hbao, denoise, temporal and bake");
}

py::list specs_of(const std::string& table) {
  return with_table(table, [](const auto& specs) { return specs_list(specs); });
}

// Throws std::invalid_argument for a name the table lacks or a value outside its range.
void check_settings(const std::string& table, const py::dict& values) {
  with_table(table, [&](const auto& specs) { settings_of(specs, table, values).validate(); });
}

// A settings class's docstring: `intro`, then each setting with what it means, its default and its range.
template <typename Settings>
std::string documented(const std::string& intro, const std::vector<SettingSpecOf<Settings>>& specs) {
  std::string doc = intro + "\n";
  for (const SettingSpecOf<Settings>& spec : specs)
    doc += "\n" + spec.name + ": " + spec.doc + " Default " +
           py::repr(to_python(spec, spec.default_value())).template cast<std::string>() + ", allowed " + spec.range() +
           ".";
  return doc;
}

// A settings struct made from its constructor's arguments, in its members' order, and checked.
template <typename Settings, typename... Args>
Settings validated(Args... args) {
  const Settings settings{args...};
  settings.validate();
  return settings;
}

// A settings class's members from its table: a read-only property per
// setting, pickling as the tuple of their values, and a repr naming each.
template <typename Settings>
void add_table_members(py::class_<Settings>& cls, const std::string& name,
                       const std::vector<SettingSpecOf<Settings>>& specs) {
  for (const SettingSpecOf<Settings>& spec : specs)
    cls.def_property_readonly(spec.name.c_str(), [&spec](const Settings& s) { return to_python(spec, spec.get(s)); });
  cls.def(py::pickle(
      [&specs](const Settings& s) {
        py::tuple values(specs.size());
        for (std::size_t i = 0; i < specs.size(); ++i) values[i] = to_python(specs[i], specs[i].get(s));
        return values;
      },
      [&specs](const py::tuple& values) {
        if (values.size() != specs.size()) throw std::invalid_argument("a pickled settings tuple of the wrong size");
        Settings s;
        for (std::size_t i = 0; i < specs.size(); ++i) specs[i].set(s, from_python(specs[i], values[i]));
        s.validate();
        return s;
      }));
  cls.def("__repr__", [&specs, name](const Settings& s) {
    std::string text = name + "(";
    for (std::size_t i = 0; i < specs.size(); ++i)
      text += (i ? ", " : "") + specs[i].name + "=" +
              py::repr(to_python(specs[i], specs[i].get(s))).template cast<std::string>();
    return text + ")";
  });
}

py::tuple render(const std::shared_ptr<Scene>& scene, const std::optional<Camera>& camera, const DeviceInfo& device,
                 const py::dict& values, const py::object& progress, const HbaoSettings& hbao,
                 const std::optional<DenoiseSettings>& denoise, TemporalHistory* history) {
  RenderSettings settings = settings_from(values);
  settings.hbao = hbao;
  settings.denoise = denoise;
  const Renderer::TileCallback between_tiles = tile_callback(progress);
  RenderResult result;
  {
    py::gil_scoped_release release;
    const Camera view = camera ? *camera : scene->default_camera(float(settings.width) / float(settings.height));
    result = Renderer::for_device(device).render(scene, view, settings, between_tiles, history);
  }
  const py::ssize_t h = result.height, w = result.width;
  const py::object variance =
      settings.variance ? py::object(adopt(std::move(result.variance), {h, w})) : py::object(py::none());
  const py::object history_length =
      history ? py::object(adopt(std::move(result.history_length), {h, w})) : py::object(py::none());
  return py::make_tuple(adopt(std::move(result.ao), {h, w}), adopt(std::move(result.coverage), {h, w}), variance,
                        history_length, stats_dict(result.stats));
}

py::tuple gbuffer(const std::shared_ptr<Scene>& scene, const std::optional<Camera>& camera, const DeviceInfo& device,
                  const py::dict& values) {
  const RenderSettings settings = settings_from(values);
  RenderResult result;
  {
    py::gil_scoped_release release;
    const Camera view = camera ? *camera : scene->default_camera(float(settings.width) / float(settings.height));
    result = Renderer::for_device(device).gbuffer(scene, view, settings);
  }
  // kernels/mbao/gbuffer.h's planes, in its order.
  static const char* const names[] = {"x",         "y",     "z",  "t",  "nx", "ny",      "nz",
                                      "footprint", "depth", "sx", "sy", "sz", "triangle"};
  static_assert(std::size(names) == GBUFFER_PLANES, "a name for each plane of the G-buffer");
  const py::ssize_t h = result.height, w = result.width;
  const py::array_t<float> planes = adopt(std::move(result.gbuffer), {py::ssize_t(GBUFFER_PLANES), h, w});
  py::dict by_name;
  for (py::ssize_t plane = 0; plane < py::ssize_t(GBUFFER_PLANES); ++plane)
    by_name[names[plane]] = planes[py::int_(plane)];
  const glm::vec3 origin = scene->render_origin();
  return py::make_tuple(by_name, py::make_tuple(origin.x, origin.y, origin.z), stats_dict(result.stats));
}

py::tuple trace(const std::shared_ptr<Scene>& scene, const py::array_t<float, py::array::c_style>& origins,
                const py::array_t<float, py::array::c_style>& directions, const DeviceInfo& device, bool any_hit,
                const std::string& traversal, bool traversal_stats) {
  const std::size_t n = std::size_t(origins.shape(0));
  std::vector<cl_float4> o(n), d(n);
  for (std::size_t i = 0; i < n; ++i) {
    o[i] = {{origins.at(i, 0), origins.at(i, 1), origins.at(i, 2), 0.0f}};
    d[i] = {{directions.at(i, 0), directions.at(i, 1), directions.at(i, 2), directions.at(i, 3)}};
  }
  const Traversal mode = parse_traversal(traversal);
  TraceResult traced;
  {
    py::gil_scoped_release release;
    traced = Renderer::for_device(device).trace(scene, o, d, any_hit, mode, traversal_stats);
  }
  const std::vector<RayHit>& hits = traced.hits;
  std::vector<float> t(n), barycentrics(2 * n);
  std::vector<std::int64_t> triangle(n);
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = hits[i].t;
    triangle[i] = hits[i].triangle == 0xFFFFFFFFu ? -1 : std::int64_t(hits[i].triangle);
    barycentrics[2 * i] = hits[i].b1;
    barycentrics[2 * i + 1] = hits[i].b2;
  }
  const auto rows = py::ssize_t(n);
  py::tuple result = py::make_tuple(adopt(std::move(t), {rows}), adopt(std::move(triangle), {rows}),
                                    adopt(std::move(barycentrics), {rows, 2}));
  if (!traversal_stats) return result;
  std::vector<std::uint32_t> counts(4 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 4; ++k) counts[4 * i + std::size_t(k)] = traced.counts[i].s[k];
  return py::make_tuple(result[0], result[1], result[2], adopt(std::move(counts), {rows, 4}));
}

}  // namespace

// A settings class from its table: documented by it, constructed from `Args`
// (the constructor's keywords, `arguments`, restating the table's names and
// defaults as a real signature; a test holds them equal) and checked, with the
// table's members.
template <typename Settings, typename... Args, typename... Keywords>
void bind_settings_class(py::module_& m, const char* name, const std::string& intro,
                         const std::vector<SettingSpecOf<Settings>>& specs, const Keywords&... arguments) {
  py::class_<Settings> cls(m, name, documented(intro, specs).c_str());
  cls.def(py::init(&validated<Settings, Args...>), arguments...);
  add_table_members(cls, name, specs);
}

void bind_render(py::module_& m) {
  m.attr("DEFAULT_MAX_RAYS") = kDefaultMaxRays;
  bind_settings_class<HbaoSettings, std::int64_t, std::int64_t, float, float>(
      m, "HBAO", "HBAO's settings (SPEC 4; Bavoil et al. 2008) for render(method=\"hbao\").", hbao_setting_specs(),
      py::arg("directions") = HbaoSettings{}.directions, py::arg("steps") = HbaoSettings{}.steps,
      py::arg("angle_bias_deg") = HbaoSettings{}.angle_bias_deg, py::arg("falloff") = HbaoSettings{}.falloff);
  bind_settings_class<DenoiseSettings, std::int64_t, float, std::int64_t, float>(
      m, "Denoise",
      "The spatial filter's settings (SPEC 7.3) for render(denoise=...): an edge-aware a-trous wavelet\n"
      "filter (Dammertz et al. 2010) guided by the camera hits' G-buffer and each pixel's variance, as\n"
      "in SVGF (Schied et al. 2017).",
      denoise_setting_specs(), py::arg("iterations") = DenoiseSettings{}.iterations,
      py::arg("sigma_plane") = DenoiseSettings{}.sigma_plane, py::arg("sigma_normal") = DenoiseSettings{}.sigma_normal,
      py::arg("sigma_value") = DenoiseSettings{}.sigma_value);
  bind_settings_class<TemporalSettings, std::int64_t>(
      m, "Temporal",
      "Temporal accumulation's settings (SPEC 7.4) for render_sequence(temporal=...): each frame\n"
      "blends its render with the history of the frames before, reprojected into its camera through\n"
      "the G-buffers.",
      temporal_setting_specs(), py::arg("max_length") = TemporalSettings{}.max_length);
  py::class_<TemporalHistory>(m, "TemporalHistory",
                              "What a sequence's frames keep on the device for the next (SPEC 7.4); "
                              "mbao.render_sequence makes one per sequence.")
      .def(py::init<const TemporalSettings&>(), py::arg("settings"));
  m.def("render", &render, py::arg("scene"), py::arg("camera"), py::arg("device"), py::arg("settings"),
        py::arg("progress"), py::arg("hbao"), py::arg("denoise"), py::arg("history"),
        "Renders; returns (ao, coverage in 255ths, variance or None, history lengths or None, stats). settings: "
        "{name: value} of setting_specs(); history: a TemporalHistory or None. Use mbao.render or "
        "mbao.render_sequence, which check and document the arguments.");
  m.def("gbuffer", &gbuffer, py::arg("scene"), py::arg("camera"), py::arg("device"), py::arg("settings"),
        "The G-buffer (SPEC 7.2); returns ({plane: (height, width) float32}, the scene's render origin, stats), "
        "the planes of kernels/mbao/gbuffer.h by name, positions relative to the render origin. "
        "Use mbao.gbuffer, which checks and documents the arguments.");
  m.def("check_settings", &check_settings, py::arg("table"), py::arg("values"),
        "Raises ValueError naming the first of {name: value} that `table`'s settings lack or hold out of range.");
  m.def("setting_specs", &specs_of, py::arg("table") = "render",
        "The settings of a table (\"render\", \"hbao\", \"denoise\" or \"temporal\"), each as a dict: name, group "
        "(\"render\" or \"engine\"), kind, doc, range, lo, hi, choices and default (render/setting_specs.h).");
  m.def(
      "kernel_variants",
      [] {
        std::vector<std::pair<std::string, std::string>> variants;
        for (const ProgramVariant& v : all_program_variants()) variants.emplace_back(v.file(), v.options());
        return variants;
      },
      "Every (program file, build options) a render plan can ask for (render/render_plan.h).");
  m.def(
      "ao_radius",
      [](const std::shared_ptr<Scene>& scene, const Camera& camera, std::optional<float> max_distance,
         const std::string& method) {
        RenderSettings settings;
        settings.max_distance = max_distance;
        settings.method = parse_method(method);
        const AoRadius radius = radius_for(settings, camera, *scene);
        return py::make_tuple(radius.value, radius.source);
      },
      py::arg("scene"), py::arg("camera"), py::arg("max_distance"), py::arg("method"),
      "(radius, source): the AO radius a render takes by SPEC 1's rule (render/renderer.h's radius_for).");
  m.def("trace", &trace, py::arg("scene"), py::arg("origins"), py::arg("directions"), py::arg("device"),
        py::arg("any_hit"), py::arg("traversal"), py::arg("traversal_stats"),
        "Traces (N, 3) origins along (N, 4) direction + t_max rows; returns (t, triangle, barycentrics).");
}

}  // namespace mbao::bindings
