#include "opencl/compute_context.h"

#include <map>
#include <mutex>

namespace mbao {
namespace {

cl::Context make_context(const DeviceInfo& device) {
  try {
    return cl::Context(device.device);
  } catch (const cl::Error& e) {
    throw_device_error("creating an OpenCL context on " + device.description(), e);
  }
}

cl::CommandQueue make_queue(const cl::Context& context, const DeviceInfo& device) {
  try {
    return cl::CommandQueue(context, device.device);
  } catch (const cl::Error& e) {
    throw_device_error("creating a command queue on " + device.description(), e);
  }
}

}  // namespace

ComputeContext::ComputeContext(DeviceInfo device)
    : device_(std::move(device)),
      context_(make_context(device_)),
      queue_(make_queue(context_, device_)),
      programs_(context_, device_.device) {}

std::shared_ptr<ComputeContext> ComputeContext::for_device(const DeviceInfo& device) {
  static std::mutex mutex;
  // Never destroyed: releasing OpenCL objects during static destruction can
  // run after the driver has been unloaded.
  static auto* contexts = new std::map<cl_device_id, std::shared_ptr<ComputeContext>>;
  std::lock_guard<std::mutex> lock(mutex);
  std::shared_ptr<ComputeContext>& context = (*contexts)[device.device()];
  if (!context) context = std::make_shared<ComputeContext>(device);
  return context;
}

}  // namespace mbao
