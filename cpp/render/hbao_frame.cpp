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
  cl_uint arg = set_camera_args(gbuffer_, scene.set_args(gbuffer_), camera, s);
  gbuffer_.setArg(arg++, positions_);
  gbuffer_.setArg(arg++, normals_);
  gbuffer_group_ = work_group_size_for(gbuffer_, device, s.work_group_size);

  hbao_ = cl::Kernel(program, "hbao");
  arg = 0;
  hbao_.setArg(arg++, positions_);
  hbao_.setArg(arg++, normals_);
  hbao_.setArg(arg++, cl_uint(s.width));
  hbao_.setArg(arg++, cl_uint(s.height));
  hbao_.setArg(arg++, CameraBasis(camera).tan_half_vfov);
  hbao_.setArg(arg++, s.max_distance);
  hbao_.setArg(arg++, float(std::sin(s.hbao.angle_bias_deg * M_PI / 180.0)));
  hbao_.setArg(arg++, s.hbao.falloff);
  hbao_.setArg(arg++, cl_uint(s.hbao.directions));
  hbao_.setArg(arg++, cl_uint(s.hbao.steps));
  hbao_.setArg(arg++, seed_words(s.seed));
  hbao_.setArg(arg++, ao_);
  hbao_.setArg(arg++, coverage_);
  hbao_group_ = work_group_size_for(hbao_, device, s.work_group_size);
}

void HbaoFrame::enqueue(cl::CommandQueue& queue) {
  launch(queue, gbuffer_, pixels_, gbuffer_group_);
  launch(queue, hbao_, pixels_, hbao_group_);
}

void HbaoFrame::enqueue_read_back(cl::CommandQueue& queue, float* ao, std::uint8_t* mask) {
  queue.enqueueReadBuffer(ao_, CL_FALSE, 0, pixels_ * sizeof(cl_float), ao);
  queue.enqueueReadBuffer(coverage_, CL_FALSE, 0, pixels_ * sizeof(cl_uchar), mask);
}

}  // namespace mbao
