// Runs a test's kernel on the default device and reads back what it wrote.
#pragma once

#include <string>
#include <vector>

#include "opencl/devices.h"
#include "opencl/kernel_args.h"

namespace mbao {

// Builds `source`, runs its kernel `name` over n work items with `args` as its
// first arguments and a buffer of n T's as its last, and returns that buffer.
template <typename T, typename... Args>
std::vector<T> device_outputs(const std::string& source, const char* name, std::size_t n, const Args&... args) {
  const DeviceInfo device = default_device();
  const cl::Context context(device.device);
  cl::CommandQueue queue(context, device.device);
  cl::Program program(context, source);
  program.build(device.device);
  cl::Kernel kernel(program, name);
  cl::Buffer out(context, CL_MEM_WRITE_ONLY, n * sizeof(T));
  set_kernel_args(kernel, args..., out);
  queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(n));
  std::vector<T> values(n);
  queue.enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(T), values.data());
  return values;
}

}  // namespace mbao
