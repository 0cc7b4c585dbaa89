#include "render/denoiser.h"

#include <utility>

#include "opencl/kernel_args.h"
#include "opencl/launch.h"

namespace mbao {
Denoiser::Denoiser(const cl::Context& context, const cl::Device& device, const cl::Program& program,
                   std::size_t width, std::size_t height, const DenoiseSettings& settings,
                   std::size_t work_group_size)
    : width_(width), height_(height), settings_(settings) {
  settings_.validate();
  const std::size_t bytes = width * height * sizeof(cl_float);
  ao_ = cl::Buffer(context, CL_MEM_READ_WRITE, bytes);
  variance_ = cl::Buffer(context, CL_MEM_READ_WRITE, bytes);
  blurred_ = cl::Buffer(context, CL_MEM_READ_WRITE, bytes);
  blur_ = cl::Kernel(program, "denoise_blur_variance");
  atrous_ = cl::Kernel(program, "denoise_atrous");
  blur_group_ = work_group_size_for(blur_, device, work_group_size);
  atrous_group_ = work_group_size_for(atrous_, device, work_group_size);
}

void Denoiser::enqueue(cl::CommandQueue& queue, const cl::Buffer& gbuffer, const cl::Buffer& ao,
                       const cl::Buffer& variance) {
  const std::size_t pixels = width_ * height_;
  const cl_uint width = cl_uint(width_), height = cl_uint(height_);
  // Each iteration reads one pair of buffers and writes the other.
  cl::Buffer from_ao = ao, from_variance = variance, to_ao = ao_, to_variance = variance_;
  for (std::int64_t i = 0; i < settings_.iterations; ++i) {
    set_kernel_args(blur_, gbuffer, from_variance, width, height, blurred_);
    launch(queue, blur_, pixels, blur_group_);
    set_kernel_args(atrous_, gbuffer, from_ao, from_variance, blurred_, width, height, cl_uint(1u << i),
                    settings_.sigma_plane, cl_uint(settings_.sigma_normal), settings_.sigma_value, to_ao,
                    to_variance);
    launch(queue, atrous_, pixels, atrous_group_);
    std::swap(from_ao, to_ao);
    std::swap(from_variance, to_variance);
  }
  if (from_ao() != ao()) {  // an odd count ends in the scratch pair
    queue.enqueueCopyBuffer(from_ao, ao, 0, 0, pixels * sizeof(cl_float));
    queue.enqueueCopyBuffer(from_variance, variance, 0, 0, pixels * sizeof(cl_float));
  }
}

}  // namespace mbao
