// Declarations shared by the binding files; each binds one part of the core.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <vector>

#include "accel/kd_tree.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "render/renderer.h"

namespace mbao::bindings {

void bind_scene(pybind11::module_& m);
void bind_devices(pybind11::module_& m);
void bind_render(pybind11::module_& m);
void bind_bake(pybind11::module_& m);

// The kd-tree statistics as the Python API reports them.
pybind11::dict tree_stats_dict(const KdTreeStats& stats);
// A render's statistics as the Python API reports them.
pybind11::dict stats_dict(const RenderStats& stats);
// Settings from {name: value} of setting_specs(), each set through its spec.
RenderSettings settings_from(const pybind11::dict& values);
// Between tiles: Ctrl-C stops the work, and progress(done, total), unless None, is told.
Renderer::TileCallback tile_callback(const pybind11::object& progress);

// Hands a vector to numpy without copying: the array owns it.
template <typename T>
pybind11::array_t<T> adopt(std::vector<T>&& data, std::vector<pybind11::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(data));
  pybind11::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return pybind11::array_t<T>(shape, owned->data(), free_when_done);
}

}  // namespace mbao::bindings
