#include "render/denoiser.h"

#include <algorithm>
#include <utility>

#include "opencl/kernel_args.h"
#include "opencl/launch.h"

namespace mbao {
Denoiser::Denoiser(const cl::Context& context, const cl::Device& device, const cl::Program& program, std::size_t width,
                   std::size_t height, const DenoiseSettings& settings, std::size_t work_group_size)
    : width_(width), height_(height), settings_(settings) {
  settings_.validate();
  const std::size_t bytes = width * height * sizeof(cl_float);
  ao_ = cl::Buffer(context, CL_MEM_READ_WRITE, bytes);
  variance_ = cl::Buffer(context, CL_MEM_READ_WRITE, bytes);
  interior_ = cl::Kernel(program, "denoise_atrous_interior");
  border_ = cl::Kernel(program, "denoise_atrous_border");
  interior_group_ = work_group_size_for(interior_, device, work_group_size);
  border_group_ = work_group_size_for(border_, device, work_group_size);
}

void Denoiser::enqueue(cl::CommandQueue& queue, const cl::Buffer& gbuffer, const cl::Buffer& ao,
                       const cl::Buffer& variance) {
  const cl_uint width = cl_uint(width_), height = cl_uint(height_);
  // Each iteration reads one pair of buffers and writes the other.
  cl::Buffer from_ao = ao, from_variance = variance, to_ao = ao_, to_variance = variance_;
  for (std::int64_t i = 0; i < settings_.iterations; ++i) {
    const std::size_t step = std::size_t(1) << i;
    for (cl::Kernel* kernel : {&interior_, &border_})
      set_kernel_args(*kernel, gbuffer, from_ao, from_variance, width, height, cl_uint(step), settings_.sigma_plane,
                      cl_uint(settings_.sigma_normal), settings_.sigma_value, to_ao, to_variance);
    // The interior is columns [2 step, width - 2 step); the border the rest (denoise.cl).
    if (width_ > 4 * step) launch_rows(queue, interior_, width_ - 4 * step, height_, interior_group_);
    launch(queue, border_, std::min(4 * step, width_) * height_, border_group_);
    std::swap(from_ao, to_ao);
    std::swap(from_variance, to_variance);
  }
  if (from_ao() != ao()) {  // an odd count ends in the scratch pair
    const std::size_t bytes = width_ * height_ * sizeof(cl_float);
    queue.enqueueCopyBuffer(from_ao, ao, 0, 0, bytes);
    queue.enqueueCopyBuffer(from_variance, variance, 0, 0, bytes);
  }
}

}  // namespace mbao
