// set_kernel_args sets a kernel's arguments in order and refuses a count that
// is not the kernel's.
#include <gtest/gtest.h>

#include <string>

#include "device_outputs.h"
#include "opencl/devices.h"
#include "opencl/kernel_args.h"

namespace mbao {
namespace {

const char* kSource = R"(
__kernel void null_or_value(__global const uint* maybe, uint value, __global uint* out) {
  out[get_global_id(0)] = maybe ? maybe[0] : value;
}
)";

// Two values that the kernel reads as one group of parameters.
struct Pair {
  cl_uint first, second;
  void append_to(KernelArgs& args) const {
    args.append(first);
    args.append(second);
  }
};

TEST(KernelArgs, AnEmptyBufferIsNullInTheKernel) {
  EXPECT_EQ(device_outputs<cl_uint>(kSource, "null_or_value", 1, cl::Buffer(), cl_uint(7)), std::vector<cl_uint>{7});
}

TEST(KernelArgs, ACountThatIsNotTheKernelsIsRefusedNamingTheKernel) {
  const cl::Context context(default_device().device);
  cl::Program program(context, kSource);
  program.build();
  cl::Kernel kernel(program, "null_or_value");
  const cl::Buffer out(context, CL_MEM_WRITE_ONLY, sizeof(cl_uint));
  const auto refusal = [&](const auto&... args) -> std::string {
    try {
      set_kernel_args(kernel, args...);
    } catch (const std::logic_error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(refusal(cl::Buffer(), cl_uint(1)), "kernel null_or_value takes 3 arguments, given 2");
  // A group counts as its members: here one too many.
  EXPECT_NE(refusal(cl::Buffer(), Pair{1, 2}, out).find("kernel null_or_value refused argument 2"), std::string::npos);
  // A buffer where the kernel takes a uint.
  EXPECT_NE(refusal(cl::Buffer(), out, out).find("kernel null_or_value refused argument 1"), std::string::npos);
  EXPECT_EQ(refusal(cl::Buffer(), cl_uint(1), out), "");
}

}  // namespace
}  // namespace mbao
