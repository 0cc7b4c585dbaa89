#include "opencl/devices.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "core/error.h"

namespace mbao {
namespace {

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return text;
}

std::string trimmed(std::string text) {
  while (!text.empty() && (text.back() == '\0' || std::isspace(static_cast<unsigned char>(text.back()))))
    text.pop_back();
  return text;
}

std::string type_name(cl_device_type type) {
  if (type & CL_DEVICE_TYPE_GPU) return "GPU";
  if (type & CL_DEVICE_TYPE_CPU) return "CPU";
  if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

std::string available_list(const std::vector<DeviceInfo>& devices) {
  std::string text;
  for (const DeviceInfo& d : devices) text += "\n  " + std::to_string(d.index) + ": " + d.description();
  return text;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error& e) {
    if (e.err() != -1001 /* CL_PLATFORM_NOT_FOUND_KHR */) throw_device_error("listing OpenCL platforms", e);
  }
  std::vector<DeviceInfo> devices;
  for (const cl::Platform& platform : platforms) {
    std::vector<cl::Device> platform_devices;
    try {
      platform.getDevices(CL_DEVICE_TYPE_ALL, &platform_devices);
    } catch (const cl::Error& e) {
      if (e.err() != CL_DEVICE_NOT_FOUND) throw_device_error("listing OpenCL devices", e);
    }
    for (const cl::Device& device : platform_devices) {
      DeviceInfo info;
      info.index = devices.size();
      info.name = trimmed(device.getInfo<CL_DEVICE_NAME>());
      info.platform = trimmed(platform.getInfo<CL_PLATFORM_NAME>());
      info.vendor = trimmed(device.getInfo<CL_DEVICE_VENDOR>());
      info.type = type_name(device.getInfo<CL_DEVICE_TYPE>());
      info.version = trimmed(device.getInfo<CL_DEVICE_VERSION>());
      info.nvidia_compiler_options =
          device.getInfo<CL_DEVICE_EXTENSIONS>().find("cl_nv_compiler_options") != std::string::npos;
      info.device = device;
      devices.push_back(std::move(info));
    }
  }
  if (devices.empty())
    throw DeviceError(
        "no OpenCL device found: install an OpenCL driver (e.g. Debian's pocl-opencl-icd for the CPU) "
        "and check that /etc/OpenCL/vendors lists it");
  return devices;
}

DeviceInfo find_device(std::size_t index) {
  const std::vector<DeviceInfo> devices = list_devices();
  if (index >= devices.size())
    throw std::invalid_argument("device: index " + std::to_string(index) +
                                " is out of range; the devices are:" + available_list(devices));
  return devices[index];
}

DeviceInfo find_device(const std::string& name_part) {
  const std::vector<DeviceInfo> devices = list_devices();
  const std::string wanted = lowercase(name_part);
  for (const DeviceInfo& d : devices)
    if (lowercase(d.description()).find(wanted) != std::string::npos) return d;
  throw std::invalid_argument("device: no device matches \"" + name_part +
                              "\"; the devices are:" + available_list(devices));
}

DeviceInfo find_device(cl_device_id handle) {
  for (const DeviceInfo& d : list_devices())
    if (d.device() == handle) return d;
  throw std::invalid_argument("device: the given OpenCL device handle is not one of this process's devices");
}

namespace {

// $MBAO_DEVICE: an index or a part of a device's name.
DeviceInfo find_device_named_by(const std::string& text) {
  if (text.find_first_not_of("0123456789") != std::string::npos) return find_device(text);
  // Longer digit strings do not fit 64 bits; any index that long is out of range anyway.
  return find_device(text.size() > 18 ? std::numeric_limits<std::size_t>::max() : std::size_t(std::stoull(text)));
}

}  // namespace

DeviceInfo default_device() {
  if (const char* chosen = std::getenv("MBAO_DEVICE"); chosen && *chosen) {
    try {
      return find_device_named_by(chosen);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("MBAO_DEVICE=\"") + chosen + "\" names no device: " + e.what());
    }
  }
  const std::vector<DeviceInfo> devices = list_devices();
  for (const DeviceInfo& d : devices)
    if (d.type == "GPU") return d;
  return devices.front();
}

}  // namespace mbao
