// The one way mbao includes the Khronos C++ bindings: OpenCL 1.2 API (what
// both PoCL and NVIDIA provide), errors as exceptions.
#pragma once

#ifndef CL_HPP_TARGET_OPENCL_VERSION
#define CL_HPP_TARGET_OPENCL_VERSION 120
#endif
#ifndef CL_HPP_MINIMUM_OPENCL_VERSION
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#endif
#ifndef CL_HPP_ENABLE_EXCEPTIONS
#define CL_HPP_ENABLE_EXCEPTIONS
#endif
#include <CL/opencl.hpp>

#include <string>

namespace mbao {

// "CL_OUT_OF_RESOURCES (-5)" and the like, for error messages.
std::string cl_error_name(cl_int code);

// Turns an OpenCL exception into mbao::DeviceError, saying what was being done.
[[noreturn]] void throw_device_error(const std::string& doing, const cl::Error& error);

}  // namespace mbao
