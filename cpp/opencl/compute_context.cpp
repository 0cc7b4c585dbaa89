#include "opencl/compute_context.h"

namespace mbao {
namespace {

cl::Context make_context(const DeviceInfo& device) {
  try {
    return cl::Context(device.device);
  } catch (const cl::Error& e) {
    throw_device_error("creating an OpenCL context on " + device.description(), e);
  }
}

cl::CommandQueue make_queue(const cl::Context& context, const DeviceInfo& device, QueueTiming timing) {
  try {
    return cl::CommandQueue(context, device.device, timing == QueueTiming::On ? CL_QUEUE_PROFILING_ENABLE : 0);
  } catch (const cl::Error& e) {
    throw_device_error("creating a command queue on " + device.description(), e);
  }
}

}  // namespace

ComputeContext::ComputeContext(DeviceInfo device, QueueTiming timing)
    : device_(std::move(device)),
      context_(make_context(device_)),
      queue_(make_queue(context_, device_, timing)),
      programs_(context_, device_.device, ProgramBinaryStore(ProgramBinaryStore::default_directory())) {}

}  // namespace mbao
