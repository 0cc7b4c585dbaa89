#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bake/bake_estimates.h"
#include "bake/bake_settings.h"
#include "bake/dilation.h"
#include "bake/lightmap_uvs.h"
#include "bake/texel_layout.h"
#include "bake/vertex_points.h"
#include "bindings/bindings.h"

#include <cstring>

namespace py = pybind11;

namespace mbao::bindings {
namespace {

// Vertices in no particular order: a layout as wide as a texture's, so tiles are not tiny on a GPU.
constexpr std::size_t kVertexLayoutWidth = 1024;

using TriangleArray = py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>;

// The triangles a vertex bake bakes, each an index into the scene's.
std::vector<std::uint32_t> baked_triangles(const Scene& scene, const TriangleArray& triangles) {
  if (triangles.ndim() != 1) throw std::invalid_argument("triangles must be one-dimensional");
  std::vector<std::uint32_t> out(triangles.data(), triangles.data() + triangles.size());
  for (const std::uint32_t t : out)
    if (t >= scene.mesh().triangles.size())
      throw std::invalid_argument("triangles: " + std::to_string(t) + " is not a triangle of a scene of " +
                                  std::to_string(scene.mesh().triangles.size()));
  return out;
}

py::tuple bake_vertices(const std::shared_ptr<Scene>& scene, const TriangleArray& triangles, const DeviceInfo& device,
                        const py::dict& values, std::int64_t samples, const py::object& progress) {
  const std::vector<std::uint32_t> baked = baked_triangles(*scene, triangles);
  const RenderSettings settings = settings_from(values);
  const Renderer::TileCallback between_tiles = tile_callback(progress);
  BakeEstimates bake;
  {
    py::gil_scoped_release release;
    const VertexPoints points(scene->mesh(), baked);
    bake = bake_estimates(Renderer::for_device(device), scene, settings, samples, points, kVertexLayoutWidth,
                          between_tiles);
  }
  const auto n = py::ssize_t(bake.values.size());
  return py::make_tuple(adopt(std::move(bake.values), {n}), adopt(std::move(bake.standard_error), {n}),
                        stats_dict(bake.stats));
}

// A texel layout with the scene whose triangles it maps.
struct SceneTexels {
  std::shared_ptr<Scene> scene;
  TexelLayout layout;
};

std::vector<glm::vec2> corner_uvs_from(const py::array_t<float, py::array::c_style | py::array::forcecast>& uvs) {
  if (uvs.ndim() != 3 || uvs.shape(1) != 3 || uvs.shape(2) != 2)
    throw std::invalid_argument("texcoords must have shape (triangles, 3, 2)");
  std::vector<glm::vec2> out(std::size_t(uvs.shape(0)) * 3);
  std::memcpy(out.data(), uvs.data(), out.size() * sizeof(glm::vec2));
  return out;
}

SceneTexels make_texels(const std::shared_ptr<Scene>& scene,
                        const py::array_t<float, py::array::c_style | py::array::forcecast>& uvs,
                        const std::vector<std::uint32_t>& triangles, int width, int height, const std::string& wrap_s,
                        const std::string& wrap_t) {
  const std::vector<glm::vec2> texcoords = corner_uvs_from(uvs);
  py::gil_scoped_release release;
  return SceneTexels{scene, TexelLayout(scene->mesh(), triangles, texcoords, width, height, parse_wrap_mode(wrap_s),
                                        parse_wrap_mode(wrap_t))};
}

void check_padding(int padding) {
  BakeSettings asked;
  asked.padding = padding;
  asked.validate();
}

py::tuple bake_texels(const SceneTexels& texels, const DeviceInfo& device, const py::dict& values, std::int64_t samples,
                      int padding, const py::object& progress) {
  check_padding(padding);
  const RenderSettings settings = settings_from(values);
  const Renderer::TileCallback between_tiles = tile_callback(progress);
  const TexelLayout& layout = texels.layout;
  BakeEstimates bake;
  std::vector<std::uint8_t> filled;
  {
    py::gil_scoped_release release;
    bake = bake_estimates(Renderer::for_device(device), texels.scene, settings, samples, layout,
                          std::size_t(layout.width()), between_tiles);
    filled = dilate(layout.covered(), layout.width(), layout.height(), padding, {&bake.values, &bake.standard_error});
  }
  const py::ssize_t h = layout.height(), w = layout.width();
  return py::make_tuple(adopt(std::move(bake.values), {h, w}), adopt(std::move(bake.standard_error), {h, w}),
                        adopt(std::move(filled), {h, w}), stats_dict(bake.stats));
}

// A bake split by the positions of its one image (Renderer::bake): each part
// traced where it is given (a worker), the whole finished where the parts meet.
using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

std::vector<float> floats_of(const FloatArray& values) {
  return std::vector<float>(values.data(), values.data() + values.size());
}

py::tuple traced_tuple(TracedPositions&& traced) {
  const auto n = py::ssize_t(traced.mean.size());
  return py::make_tuple(adopt(std::move(traced.mean), {n}), adopt(std::move(traced.second_moment), {n}),
                        stats_dict(traced.stats));
}

std::size_t vertex_bake_positions(const std::shared_ptr<Scene>& scene, const TriangleArray& triangles,
                                  std::int64_t samples) {
  const std::vector<std::uint32_t> baked = baked_triangles(*scene, triangles);
  py::gil_scoped_release release;
  return bake_layout(VertexPoints(scene->mesh(), baked), samples, kVertexLayoutWidth).positions();
}

py::tuple trace_vertex_bake(const std::shared_ptr<Scene>& scene, const TriangleArray& triangles,
                            const DeviceInfo& device, const py::dict& values, std::int64_t samples, std::size_t first,
                            std::size_t end, const py::object& progress) {
  const std::vector<std::uint32_t> baked = baked_triangles(*scene, triangles);
  const RenderSettings settings = settings_from(values);
  const Renderer::TileCallback between_tiles = tile_callback(progress);
  TracedPositions traced;
  {
    py::gil_scoped_release release;
    const VertexPoints points(scene->mesh(), baked);
    const BakeLayout layout = bake_layout(points, samples, kVertexLayoutWidth);
    traced = trace_bake(Renderer::for_device(device), scene, settings, points, layout, first, end, between_tiles);
  }
  return traced_tuple(std::move(traced));
}

py::tuple finish_vertex_bake(const std::shared_ptr<Scene>& scene, const TriangleArray& triangles, std::int64_t samples,
                             const FloatArray& mean, const FloatArray& second_moment) {
  const std::vector<std::uint32_t> baked = baked_triangles(*scene, triangles);
  const std::vector<float> means = floats_of(mean), second_moments = floats_of(second_moment);
  BakeEstimates bake;
  {
    py::gil_scoped_release release;
    const VertexPoints points(scene->mesh(), baked);
    bake = finish_bake(points, bake_layout(points, samples, kVertexLayoutWidth), samples, means, second_moments);
  }
  const auto n = py::ssize_t(bake.values.size());
  return py::make_tuple(adopt(std::move(bake.values), {n}), adopt(std::move(bake.standard_error), {n}));
}

py::tuple trace_texel_bake(const SceneTexels& texels, const DeviceInfo& device, const py::dict& values,
                           std::int64_t samples, std::size_t first, std::size_t end, const py::object& progress) {
  const RenderSettings settings = settings_from(values);
  const Renderer::TileCallback between_tiles = tile_callback(progress);
  TracedPositions traced;
  {
    py::gil_scoped_release release;
    const TexelLayout& layout = texels.layout;
    traced = trace_bake(Renderer::for_device(device), texels.scene, settings, layout,
                        bake_layout(layout, samples, std::size_t(layout.width())), first, end, between_tiles);
  }
  return traced_tuple(std::move(traced));
}

py::tuple finish_texel_bake(const SceneTexels& texels, std::int64_t samples, int padding, const FloatArray& mean,
                            const FloatArray& second_moment) {
  check_padding(padding);
  const std::vector<float> means = floats_of(mean), second_moments = floats_of(second_moment);
  const TexelLayout& layout = texels.layout;
  BakeEstimates bake;
  std::vector<std::uint8_t> filled;
  {
    py::gil_scoped_release release;
    bake =
        finish_bake(layout, bake_layout(layout, samples, std::size_t(layout.width())), samples, means, second_moments);
    filled = dilate(layout.covered(), layout.width(), layout.height(), padding, {&bake.values, &bake.standard_error});
  }
  const py::ssize_t h = layout.height(), w = layout.width();
  return py::make_tuple(adopt(std::move(bake.values), {h, w}), adopt(std::move(bake.standard_error), {h, w}),
                        adopt(std::move(filled), {h, w}));
}

py::tuple lightmap_uvs(const std::shared_ptr<Scene>& scene, const std::vector<std::uint32_t>& triangles, int width,
                       int height, int padding) {
  for (std::uint32_t t : triangles)
    if (t >= scene->mesh().triangles.size())
      throw std::invalid_argument("triangle " + std::to_string(t) + " does not exist");
  LightmapUvs uvs;
  {
    py::gil_scoped_release release;
    uvs = generate_lightmap_uvs(scene->mesh(), triangles, width, height, padding);
  }
  py::array_t<float> corners({py::ssize_t(triangles.size()), py::ssize_t(3), py::ssize_t(2)});
  std::memcpy(corners.mutable_data(), uvs.corner_uvs.data(), uvs.corner_uvs.size() * sizeof(glm::vec2));
  py::dict stats;
  stats["charts"] = uvs.charts;
  stats["worst_stretch"] = uvs.worst_stretch;
  stats["texels_per_unit"] = uvs.texels_per_unit;
  stats["chart_padding"] = uvs.padding;
  stats["size_keeping_padding"] =
      uvs.size_keeping_padding ? py::object(py::make_tuple(uvs.size_keeping_padding->x, uvs.size_keeping_padding->y))
                               : py::object(py::none());
  return py::make_tuple(corners, stats, SceneTexels{scene, std::move(*uvs.layout)});
}

}  // namespace

void bind_bake(py::module_& m) {
  m.def("lightmap_uvs", &lightmap_uvs, py::arg("scene"), py::arg("triangles"), py::arg("width"), py::arg("height"),
        py::arg("padding"),
        "Generated UVs for a bake (bake/lightmap_uvs.h): ((K, 3, 2) corner UVs, {charts, worst_stretch, "
        "texels_per_unit}, their TexelLayout).");
  py::class_<SceneTexels>(m, "TexelLayout",
                          "Where a UV set puts triangles of a scene in a texture (SPEC 6.3; bake/texel_layout.h).")
      .def(py::init(&make_texels), py::arg("scene"), py::arg("texcoords"), py::arg("triangles"), py::arg("width"),
           py::arg("height"), py::arg("wrap_s"), py::arg("wrap_t"))
      .def_property_readonly("width", [](const SceneTexels& t) { return t.layout.width(); })
      .def_property_readonly("height", [](const SceneTexels& t) { return t.layout.height(); })
      .def_property_readonly("covered",
                             [](const SceneTexels& t) {
                               std::vector<std::uint8_t> covered = t.layout.covered();
                               return adopt(std::move(covered), {t.layout.height(), t.layout.width()});
                             })
      .def_property_readonly("covered_count", [](const SceneTexels& t) { return t.layout.covered_count(); })
      .def_property_readonly(
          "claimed_twice", [](const SceneTexels& t) { return t.layout.claimed_twice(); },
          "Covered texels one of whose 4 x 4 sample points two triangles claim.")
      .def_property_readonly(
          "unmapped_triangles", [](const SceneTexels& t) { return t.layout.unmapped_triangles(); },
          "Triangles of zero UV area, which fall in no texel.")
      .def(
          "bake_positions",
          [](const SceneTexels& t, std::int64_t samples) {
            return bake_layout(t.layout, samples, std::size_t(t.layout.width())).positions();
          },
          py::arg("samples"), "The positions of a bake's one image, which trace_texel_bake splits.");
  m.def("bake_texels", &bake_texels, py::arg("texels"), py::arg("device"), py::arg("settings"), py::arg("samples"),
        py::arg("padding"), py::arg("progress"),
        "Bakes L_b per texel of a TexelLayout (SPEC 6.3) and dilates by `padding`; returns (image, standard_error, "
        "filled, stats). Use mbao.bake.");
  m.def("vertex_bake_positions", &vertex_bake_positions, py::arg("scene"), py::arg("triangles"), py::arg("samples"),
        "The positions of a vertex bake's one image, which trace_vertex_bake splits.");
  m.def("trace_vertex_bake", &trace_vertex_bake, py::arg("scene"), py::arg("triangles"), py::arg("device"),
        py::arg("settings"), py::arg("samples"), py::arg("first"), py::arg("end"), py::arg("progress"),
        "The positions [first, end) of a vertex bake traced: (mean, second moment, stats), by position. Any "
        "split of the positions gives the whole bake's, bit for bit. Use mbao.bake.");
  m.def("finish_vertex_bake", &finish_vertex_bake, py::arg("scene"), py::arg("triangles"), py::arg("samples"),
        py::arg("mean"), py::arg("second_moment"),
        "(values, standard_error) per vertex from every position's moments.");
  m.def("trace_texel_bake", &trace_texel_bake, py::arg("texels"), py::arg("device"), py::arg("settings"),
        py::arg("samples"), py::arg("first"), py::arg("end"), py::arg("progress"),
        "trace_vertex_bake for a TexelLayout.");
  m.def("finish_texel_bake", &finish_texel_bake, py::arg("texels"), py::arg("samples"), py::arg("padding"),
        py::arg("mean"), py::arg("second_moment"),
        "(image, standard_error, filled) of a TexelLayout from every position's moments, dilated by `padding`.");
  m.attr("BAKE_RESOLUTION_RANGE") = py::make_tuple(1, kMaxTextureSide);
  m.def("bake_vertices", &bake_vertices, py::arg("scene"), py::arg("triangles"), py::arg("device"), py::arg("settings"),
        py::arg("samples"), py::arg("progress"),
        "Bakes L_b per vertex (SPEC 6.2) over the one-rings of `triangles` (indices into the scene's; the rest only "
        "occlude); returns (values, standard_error, stats). settings: {name: value} of "
        "setting_specs(). Use mbao.bake, which checks and documents the arguments.");
}

}  // namespace mbao::bindings
