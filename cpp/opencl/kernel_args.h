#pragma once

// A kernel's arguments, all of them, set by one call in the order of its
// parameter list: set_kernel_args(kernel, scene, ao_params, cl_uint(first), hits, ...).
// The count is checked against the kernel's own (CL_KERNEL_NUM_ARGS), so a
// parameter added on one side and not the other throws at the first launch
// instead of shifting every argument after it.

#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "opencl/opencl.h"

namespace mbao {

class KernelArgs;

// A group of parameters that one object supplies in order (the scene's
// MBAO_SCENE_PARAMS, the AO settings' MBAO_AO_PARAMS): a type with
// `void append_to(KernelArgs&) const`.
template <typename T, typename = void>
struct is_argument_group : std::false_type {};
template <typename T>
struct is_argument_group<T, std::void_t<decltype(std::declval<const T&>().append_to(std::declval<KernelArgs&>()))>>
    : std::true_type {};

class KernelArgs {
 public:
  explicit KernelArgs(cl::Kernel& kernel) : kernel_(kernel) {}

  // A value, a buffer (an empty cl::Buffer is NULL in the kernel) or a group.
  // Each throws std::logic_error naming the kernel and the argument where the
  // driver refuses it (a size that is not the parameter's, an index past the last).
  template <typename T>
  void append(const T& value) {
    if constexpr (is_argument_group<T>::value)
      value.append_to(*this);
    else
      set([&] { kernel_.setArg(next_, value); });
  }
  void append(const cl::Buffer& buffer) {
    if (buffer())
      set([&] { kernel_.setArg(next_, buffer); });
    else
      set([&] { kernel_.setArg(next_, sizeof(cl_mem), nullptr); });
  }

  // Throws std::logic_error where the kernel takes another number of arguments.
  void check_complete() const {
    const cl_uint expected = kernel_.getInfo<CL_KERNEL_NUM_ARGS>();
    if (next_ != expected)
      throw std::logic_error("kernel " + name() + " takes " + std::to_string(expected) + " arguments, given " +
                             std::to_string(next_));
  }

 private:
  template <typename SetArg>
  void set(const SetArg& set_arg) {
    try {
      set_arg();
    } catch (const cl::Error& e) {
      throw std::logic_error("kernel " + name() + " refused argument " + std::to_string(next_) + " (" + e.what() +
                             ", error " + std::to_string(e.err()) + ")");
    }
    ++next_;
  }
  std::string name() const { return kernel_.getInfo<CL_KERNEL_FUNCTION_NAME>().c_str(); }

  cl::Kernel& kernel_;
  cl_uint next_ = 0;
};

template <typename... Args>
void set_kernel_args(cl::Kernel& kernel, const Args&... args) {
  KernelArgs list(kernel);
  (list.append(args), ...);
  list.check_complete();
}

}  // namespace mbao
