#include "opencl/program_cache.h"

#include "core/error.h"
#include "core/log.h"
#include "core/timer.h"
#include "opencl/kernel_sources.h"
#include "opencl/stderr_capture.h"

namespace mbao {
namespace {

// Builds `program` with what the compiler prints held back, and hands its
// build log and that text, where there is any, to the log (a failed build
// throws, its log then going into the error instead).
void build_quietly(cl::Program& program, const cl::Device& device, const std::string& source_name,
                   const std::string& options) {
  StderrCapture capture;
  program.build(device, options.c_str());
  const std::string text = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device) + capture.release();
  if (text.find_first_not_of(" \t\r\n") != std::string::npos)
    log_message("building kernels/" + source_name + " with options \"" + options + "\":\n" + text);
}

std::string identity_of(const cl::Device& device) {
  const cl::Platform platform(device.getInfo<CL_DEVICE_PLATFORM>());
  return platform.getInfo<CL_PLATFORM_NAME>() + "\n" + platform.getInfo<CL_PLATFORM_VERSION>() + "\n" +
         device.getInfo<CL_DEVICE_NAME>() + "\n" + device.getInfo<CL_DEVICE_VERSION>() + "\n" +
         device.getInfo<CL_DRIVER_VERSION>();
}

}  // namespace

std::string to_string(ProgramOrigin origin) {
  switch (origin) {
    case ProgramOrigin::Memory: return "memory";
    case ProgramOrigin::Disk: return "disk";
    default: return "compiled";
  }
}

ProgramCache::ProgramCache(cl::Context context, cl::Device device, ProgramBinaryStore store)
    : context_(std::move(context)),
      device_(std::move(device)),
      store_(std::move(store)),
      device_identity_(identity_of(device_)) {}

BuiltProgram ProgramCache::get(const std::string& source_name, const std::string& options) {
  std::string source = kernel_program_source(source_name);
  std::lock_guard<std::mutex> lock(mutex_);
  auto key = std::make_pair(std::move(source), options);
  if (const auto found = programs_.find(key); found != programs_.end())
    return {found->second, 0.0, ProgramOrigin::Memory};

  Stopwatch clock;
  const std::string disk_key = device_identity_ + "\n" + options + "\n" + key.first;
  BuiltProgram built;
  if (const auto binary = store_.load(disk_key)) {
    built.program = from_binary(source_name, *binary, options);
    built.origin = ProgramOrigin::Disk;
  }
  if (!built.program()) {  // nothing on disk, or a binary this driver no longer takes
    built.program = compile(source_name, key.first, options);
    built.origin = ProgramOrigin::Compiled;
    const auto binaries = built.program.getInfo<CL_PROGRAM_BINARIES>();
    if (!binaries.empty() && !binaries.front().empty()) store_.save(disk_key, binaries.front());
  }
  built.build_ms = clock.elapsed_ms();
  programs_.emplace(std::move(key), built.program);
  return built;
}

cl::Program ProgramCache::from_binary(const std::string& source_name, const std::vector<unsigned char>& binary,
                                      const std::string& options) const {
  try {
    cl::Program program(context_, {device_}, cl::Program::Binaries{binary});
    build_quietly(program, device_, source_name, options);
    return program;
  } catch (const cl::Error&) {
    return {};
  }
}

cl::Program ProgramCache::compile(const std::string& source_name, const std::string& source,
                                  const std::string& options) const {
  try {
    cl::Program program(context_, source);
    build_quietly(program, device_, source_name, options);
    return program;
  } catch (const cl::BuildError& e) {
    std::string log;
    for (const auto& entry : e.getBuildLog()) log += entry.second;
    throw DeviceError("building kernels/" + source_name + " with options \"" + options + "\" failed:\n" + log);
  } catch (const cl::Error& e) {
    throw_device_error("building kernels/" + source_name, e);
  }
}

}  // namespace mbao
