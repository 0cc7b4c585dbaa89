// The spatial filter of SPEC 7.3 on the device: an image and its variance
// filtered in place, guided by a G-buffer (kernels/denoise.cl).
#pragma once

#include <cstddef>
#include <cstdint>

#include "opencl/opencl.h"
#include "render/render_settings.h"

namespace mbao {

class Denoiser {
 public:
  // For width x height images, with the kernels of `program` (denoise.cl).
  Denoiser(const cl::Context& context, const cl::Device& device, const cl::Program& program, std::size_t width,
           std::size_t height, const DenoiseSettings& settings, std::size_t work_group_size = 0);

  // Filters `ao` and `variance` (a float per pixel, row by row) in place,
  // guided by `gbuffer` (the filters' planes, MBAO_GBUFFER_FILTER_PLANES of kernels/mbao/gbuffer.h).
  void enqueue(cl::CommandQueue& queue, const cl::Buffer& gbuffer, const cl::Buffer& ao, const cl::Buffer& variance);

  // Its own buffers: an image and a variance.
  static std::size_t device_bytes(std::size_t pixels) { return 2 * pixels * sizeof(cl_float); }

 private:
  std::size_t width_, height_;
  DenoiseSettings settings_;
  cl::Buffer ao_, variance_;
  cl::Kernel interior_, border_;
  std::size_t interior_group_ = 0, border_group_ = 0;
};

}  // namespace mbao
