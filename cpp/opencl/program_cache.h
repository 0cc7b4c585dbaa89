#pragma once

#include <map>
#include <mutex>
#include <string>
#include <utility>

#include "opencl/opencl.h"
#include "opencl/program_binary_store.h"

namespace mbao {

// Where a program came from: this process's memory, the on-disk store of an
// earlier process, or the OpenCL compiler.
enum class ProgramOrigin { Memory, Disk, Compiled };
std::string to_string(ProgramOrigin origin);

struct BuiltProgram {
  cl::Program program;
  double build_ms = 0.0;  // time spent getting it for this request
  ProgramOrigin origin = ProgramOrigin::Compiled;
};

// Programs built for one device, keyed by the source text and the build
// options: kept in memory for the life of the process, and as binaries on disk
// (keyed by the device and driver too) so that the next process does not
// compile them again.
class ProgramCache {
 public:
  ProgramCache(cl::Context context, cl::Device device, ProgramBinaryStore store);

  // Builds kernels/<source_name> with `options`, or returns it from a cache.
  // Throws DeviceError with the compiler's log if the build fails; a build
  // that succeeds hands its log, and what the compiler printed, to log_message.
  BuiltProgram get(const std::string& source_name, const std::string& options);

 private:
  cl::Program from_binary(const std::string& source_name, const std::vector<unsigned char>& binary,
                          const std::string& options) const;
  cl::Program compile(const std::string& source_name, const std::string& source, const std::string& options) const;

  cl::Context context_;
  cl::Device device_;
  ProgramBinaryStore store_;
  std::string device_identity_;  // platform, device and driver: binaries are only valid for these
  std::mutex mutex_;
  std::map<std::pair<std::string, std::string>, cl::Program> programs_;  // (source text, options)
};

}  // namespace mbao
