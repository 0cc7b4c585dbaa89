// Pickle states of the core's objects (scene_pickle.cpp): tuples of Python
// values and bytes that py::pickle hands to pickle, and back.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>

#include "scene/camera.h"
#include "scene/scene.h"

namespace mbao::bindings {

pybind11::tuple camera_state(const Camera& camera);
Camera camera_from_state(const pybind11::tuple& state);
// A scene's or a mesh's state; its kd-tree and device buffers are not part of it.
pybind11::tuple scene_state(const Scene& scene);
std::shared_ptr<Scene> scene_from_state(const pybind11::tuple& state);
std::shared_ptr<Mesh> mesh_from_state(const pybind11::tuple& state);

}  // namespace mbao::bindings
