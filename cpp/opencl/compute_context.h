#pragma once

#include <memory>

#include "opencl/devices.h"
#include "opencl/program_cache.h"

namespace mbao {

// A device with its context, in-order queue and built programs: one per
// device for the life of the process, shared by everything that uses it.
class ComputeContext {
 public:
  static std::shared_ptr<ComputeContext> for_device(const DeviceInfo& device);

  const DeviceInfo& device() const { return device_; }
  const cl::Context& context() const { return context_; }
  cl::CommandQueue& queue() { return queue_; }
  ProgramCache& programs() { return programs_; }

  explicit ComputeContext(DeviceInfo device);

 private:
  DeviceInfo device_;
  cl::Context context_;
  cl::CommandQueue queue_;
  ProgramCache programs_;
};

}  // namespace mbao
