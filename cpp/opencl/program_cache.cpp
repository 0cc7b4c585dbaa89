#include "opencl/program_cache.h"

#include "core/error.h"
#include "core/timer.h"
#include "opencl/kernel_sources.h"

namespace mbao {

BuiltProgram ProgramCache::get(const std::string& source_name, const std::string& options) {
  std::string source = kernel_program_source(source_name);
  std::lock_guard<std::mutex> lock(mutex_);
  auto key = std::make_pair(std::move(source), options);
  if (const auto found = programs_.find(key); found != programs_.end()) return {found->second, 0.0, true};

  Stopwatch clock;
  cl::Program program;
  try {
    program = cl::Program(context_, key.first);
    program.build(device_, options.c_str());
  } catch (const cl::BuildError& e) {
    std::string log;
    for (const auto& entry : e.getBuildLog()) log += entry.second;
    throw DeviceError("building kernels/" + source_name + " with options \"" + options + "\" failed:\n" + log);
  } catch (const cl::Error& e) {
    throw_device_error("building kernels/" + source_name, e);
  }
  const double build_ms = clock.elapsed_ms();
  programs_.emplace(std::move(key), program);
  return {program, build_ms, false};
}

}  // namespace mbao
