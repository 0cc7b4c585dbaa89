#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "opencl/opencl.h"

namespace mbao {

// One OpenCL device, numbered across all platforms in the order the ICD
// loader lists them.
struct DeviceInfo {
  std::size_t index = 0;
  std::string name;
  std::string platform;
  std::string vendor;
  std::string type;     // "GPU", "CPU", "accelerator" or "other"
  std::string version;  // CL_DEVICE_VERSION
  // cl_nv_compiler_options: the compiler takes NVIDIA's -cl-nv-* build options.
  bool nvidia_compiler_options = false;
  cl::Device device;

  // "platform: name", as selection by name matches it.
  std::string description() const { return platform + ": " + name; }
};

// Throws DeviceError when there is no platform or no device at all.
std::vector<DeviceInfo> list_devices();
// Throws std::invalid_argument listing the devices when `index` is out of range.
DeviceInfo find_device(std::size_t index);
// The first device whose description contains `name_part` (case-insensitive);
// throws std::invalid_argument listing the devices when none does.
DeviceInfo find_device(const std::string& name_part);
// $MBAO_DEVICE (an index or a name part) if set, else the first GPU, else the first device.
DeviceInfo default_device();
// The device behind a handle obtained elsewhere (e.g. pyopencl's Device.int_ptr).
DeviceInfo find_device(cl_device_id handle);

}  // namespace mbao
