#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bake/bake_estimates.h"
#include "bake/vertex_points.h"
#include "bindings/bindings.h"

namespace py = pybind11;

namespace mbao::bindings {
namespace {

// Vertices in no particular order: a layout as wide as a texture's, so tiles are not tiny on a GPU.
constexpr std::size_t kVertexLayoutWidth = 1024;

py::tuple bake_vertices(const std::shared_ptr<Scene>& scene, const DeviceInfo& device, const py::dict& values,
                        std::int64_t samples, const py::object& progress) {
  const RenderSettings settings = settings_from(values);
  const Renderer::TileCallback between_tiles = tile_callback(progress);
  BakeEstimates bake;
  {
    py::gil_scoped_release release;
    const VertexPoints points(scene->mesh());
    bake = bake_estimates(Renderer::for_device(device), scene, settings, samples, points, kVertexLayoutWidth,
                          between_tiles);
  }
  const auto n = py::ssize_t(bake.values.size());
  return py::make_tuple(adopt(std::move(bake.values), {n}), adopt(std::move(bake.standard_error), {n}),
                        stats_dict(bake.stats));
}

}  // namespace

void bind_bake(py::module_& m) {
  m.attr("BAKE_SAMPLES_RANGE") = py::make_tuple(kMinBakeSamples, kMaxBakeSamples);
  m.def("bake_vertices", &bake_vertices, py::arg("scene"), py::arg("device"), py::arg("settings"),
        py::arg("samples"), py::arg("progress"),
        "Bakes L_b per vertex (SPEC 6.2); returns (values, standard_error, stats). settings: {name: value} of "
        "setting_specs(). Use mbao.bake, which checks and documents the arguments.");
}

}  // namespace mbao::bindings
