#pragma once

#include <cstddef>

#include "opencl/opencl.h"
#include "render/ao_kernel_args.h"
#include "render/render_settings.h"
#include "scene/camera.h"

namespace mbao {

// HBAO (hbao.cl, SPEC 4): the image from a frame's G-buffer, written into
// that frame's image and coverage. The frame's tiles must have run.
class HbaoPass {
 public:
  HbaoPass(const cl::Device& device, const cl::Program& program, const Camera& camera, const RenderSettings& settings);

  void enqueue(cl::CommandQueue& queue, const FrameBuffers& images);

 private:
  const CameraArgs view_;
  const RenderSettings settings_;
  cl::Kernel kernel_;
  std::size_t group_ = 0;
};

}  // namespace mbao
