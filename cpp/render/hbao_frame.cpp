#include "render/hbao_frame.h"

#include <cmath>

#include "opencl/launch.h"
#include "render/ao_kernel_args.h"

namespace mbao {

std::size_t HbaoFrame::device_bytes(std::size_t pixels) {
  return pixels * (2 * sizeof(cl_float4) + sizeof(cl_float) + sizeof(cl_uchar));  // G-buffer, ao, coverage
}

HbaoFrame::HbaoFrame(const cl::Context& context, const cl::Device& device, const cl::Program& program,
                     const DeviceScene& scene, const Camera& camera, const RenderSettings& s)
    : pixels_(std::size_t(s.width) * std::size_t(s.height)) {
  positions_ = cl::Buffer(context, CL_MEM_READ_WRITE, pixels_ * sizeof(cl_float4));
  normals_ = cl::Buffer(context, CL_MEM_READ_WRITE, pixels_ * sizeof(cl_float4));
  ao_ = cl::Buffer(context, CL_MEM_WRITE_ONLY, pixels_ * sizeof(cl_float));
  coverage_ = cl::Buffer(context, CL_MEM_WRITE_ONLY, pixels_ * sizeof(cl_uchar));

  gbuffer_ = cl::Kernel(program, "hbao_gbuffer");
  set_kernel_args(gbuffer_, scene, CameraArgs(camera, s), positions_, normals_);
  gbuffer_group_ = work_group_size_for(gbuffer_, device, s.work_group_size);

  hbao_ = cl::Kernel(program, "hbao");
  set_kernel_args(hbao_, positions_, normals_, cl_uint(s.width), cl_uint(s.height), CameraBasis(camera).tan_half_vfov,
                  s.radius(), float(std::sin(s.hbao.angle_bias_deg * M_PI / 180.0)), s.hbao.falloff,
                  cl_uint(s.hbao.directions), cl_uint(s.hbao.steps), seed_words(s.seed), ao_, coverage_);
  hbao_group_ = work_group_size_for(hbao_, device, s.work_group_size);
}

void HbaoFrame::enqueue(cl::CommandQueue& queue) {
  launch(queue, gbuffer_, pixels_, gbuffer_group_);
  launch(queue, hbao_, pixels_, hbao_group_);
}

void HbaoFrame::enqueue_read_back(cl::CommandQueue& queue, float* ao, std::uint8_t* coverage) {
  queue.enqueueReadBuffer(ao_, CL_FALSE, 0, pixels_ * sizeof(cl_float), ao);
  queue.enqueueReadBuffer(coverage_, CL_FALSE, 0, pixels_ * sizeof(cl_uchar), coverage);
}

}  // namespace mbao
