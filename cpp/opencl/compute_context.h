#pragma once

#include "opencl/devices.h"
#include "opencl/program_cache.h"

namespace mbao {

// Whether a queue records when its commands ran (CL_QUEUE_PROFILING_ENABLE),
// for opencl/command_times.h.
enum class QueueTiming { Off, On };

// A device with its context, in-order queue and built programs.
class ComputeContext {
 public:
  explicit ComputeContext(DeviceInfo device, QueueTiming timing = QueueTiming::Off);

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
