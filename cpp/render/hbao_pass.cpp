#include "render/hbao_pass.h"

#include <cmath>

#include "opencl/launch.h"

namespace mbao {

HbaoPass::HbaoPass(const cl::Device& device, const cl::Program& program, const Camera& camera,
                   const RenderSettings& settings)
    : view_(camera, settings), settings_(settings), kernel_(program, "hbao") {
  group_ = work_group_size_for(kernel_, device, settings.work_group_size);
}

void HbaoPass::enqueue(cl::CommandQueue& queue, const FrameBuffers& images) {
  const HbaoSettings& h = settings_.hbao;
  set_kernel_args(kernel_, images.gbuffer, view_.width, view_.height, view_.right, view_.up, view_.forward,
                  view_.film_scale, settings_.radius(), float(std::sin(h.angle_bias_deg * M_PI / 180.0)), h.falloff,
                  cl_uint(h.directions), cl_uint(h.steps), seed_words(settings_.seed), images.ao, images.coverage);
  launch_rows(queue, kernel_, view_.width, view_.height, group_);
}

}  // namespace mbao
