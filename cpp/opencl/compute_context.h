#pragma once

#include "opencl/devices.h"
#include "opencl/program_cache.h"

namespace mbao {

// A device with its context, in-order queue and built programs.
class ComputeContext {
 public:
  explicit ComputeContext(DeviceInfo device);

  const DeviceInfo& device() const { return device_; }
  const cl::Context& context() const { return context_; }
  cl::CommandQueue& queue() { return queue_; }
  ProgramCache& programs() { return programs_; }

 private:
  DeviceInfo device_;
  cl::Context context_;
  cl::CommandQueue queue_;
  ProgramCache programs_;
};

}  // namespace mbao
