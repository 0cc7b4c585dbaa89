// Declarations shared by the binding files; each binds one part of the core.
#pragma once

#include <pybind11/pybind11.h>

#include "accel/kd_tree.h"

namespace mbao::bindings {

void bind_scene(pybind11::module_& m);
void bind_devices(pybind11::module_& m);
void bind_render(pybind11::module_& m);

// The kd-tree statistics as the Python API reports them.
pybind11::dict tree_stats_dict(const KdTreeStats& stats);

}  // namespace mbao::bindings
