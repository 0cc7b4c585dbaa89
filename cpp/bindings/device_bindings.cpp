#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>

#include "bindings/bindings.h"
#include "opencl/devices.h"

namespace py = pybind11;

namespace mbao::bindings {

void bind_devices(py::module_& m) {
  py::class_<DeviceInfo>(m, "Device", "An OpenCL device, as listed by mbao.devices().")
      .def(py::init(
          []() -> DeviceInfo { throw py::type_error("mbao.Device() makes nothing: the devices are mbao.devices()"); }))
      .def_readonly("index", &DeviceInfo::index, "Position in mbao.devices(); pass it as device=.")
      .def_readonly("name", &DeviceInfo::name)
      .def_readonly("platform", &DeviceInfo::platform)
      .def_readonly("vendor", &DeviceInfo::vendor)
      .def_readonly("type", &DeviceInfo::type, "\"GPU\", \"CPU\", \"accelerator\" or \"other\".")
      .def_readonly("version", &DeviceInfo::version)
      .def("__eq__", [](const DeviceInfo& a, const DeviceInfo& b) { return a.device() == b.device(); })
      .def("__hash__", [](const DeviceInfo& d) { return std::hash<const void*>()(d.device()); })
      .def("__repr__", [](const DeviceInfo& d) {
        return "<mbao.Device " + std::to_string(d.index) + ": " + d.description() + " (" + d.type + ")>";
      });

  m.def("devices", &list_devices, py::call_guard<py::gil_scoped_release>());
  m.def("default_device", &default_device, py::call_guard<py::gil_scoped_release>());
  m.def("find_device_by_index", py::overload_cast<std::size_t>(&find_device), py::arg("index"));
  m.def("find_device_by_name", py::overload_cast<const std::string&>(&find_device), py::arg("name"));
  m.def(
      "find_device_by_handle",
      [](std::uintptr_t handle) { return find_device(reinterpret_cast<cl_device_id>(handle)); }, py::arg("handle"),
      "The device behind a cl_device_id, e.g. pyopencl.Device.int_ptr.");
}

}  // namespace mbao::bindings
