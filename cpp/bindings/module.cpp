#include <pybind11/pybind11.h>

#include <string>

#include "bindings/bindings.h"
#include "core/error.h"
#include "core/log.h"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() = "mbao's C++ core: scenes, kd-tree, OpenCL devices and the renderer. Use the mbao package.";
  m.attr("__version__") = MBAO_VERSION;
  auto error = py::register_exception<mbao::Error>(m, "Error", PyExc_RuntimeError);
  py::register_exception<mbao::LoadError>(m, "LoadError", error.ptr());
  py::register_exception<mbao::DeviceError>(m, "DeviceError", error.ptr());
  mbao::bindings::bind_scene(m);
  mbao::bindings::bind_devices(m);
  mbao::bindings::bind_render(m);
  mbao::bindings::bind_bake(m);
  // The core's messages (compiler warnings) go to the logger "mbao", at INFO:
  // Python shows them only where the application configures logging to.
  mbao::set_log_sink([](const std::string& message) {
    py::gil_scoped_acquire gil;
    py::module_::import("logging").attr("getLogger")("mbao").attr("info")(message);
  });
}
