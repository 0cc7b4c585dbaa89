#pragma once

#include <map>
#include <mutex>
#include <string>
#include <utility>

#include "opencl/opencl.h"

namespace mbao {

struct BuiltProgram {
  cl::Program program;
  double build_ms = 0.0;    // time spent building it for this request, 0 on a cache hit
  bool cache_hit = false;
};

// Programs built for one device, kept for the life of the process and keyed by
// the source text and the build options, so each variant is compiled once.
class ProgramCache {
 public:
  ProgramCache(cl::Context context, cl::Device device) : context_(std::move(context)), device_(std::move(device)) {}

  // Builds kernels/<source_name> with `options`, or returns the cached program.
  // Throws DeviceError with the compiler's log if the build fails.
  BuiltProgram get(const std::string& source_name, const std::string& options);

 private:
  cl::Context context_;
  cl::Device device_;
  std::mutex mutex_;
  std::map<std::pair<std::string, std::string>, cl::Program> programs_;  // (source text, options)
};

}  // namespace mbao
