#include <pybind11/pybind11.h>

#include "bindings/bindings.h"
#include "core/error.h"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() = "mbao's C++ core: scenes, kd-tree, OpenCL devices and the renderer. Use the mbao package.";
  auto error = py::register_exception<mbao::Error>(m, "Error", PyExc_RuntimeError);
  py::register_exception<mbao::LoadError>(m, "LoadError", error.ptr());
  py::register_exception<mbao::DeviceError>(m, "DeviceError", error.ptr());
  mbao::bindings::bind_scene(m);
  mbao::bindings::bind_devices(m);
  mbao::bindings::bind_render(m);
  mbao::bindings::bind_bake(m);
}
