#include "render/temporal_history.h"

#include <utility>

#include "opencl/kernel_args.h"
#include "opencl/launch.h"

namespace mbao {

TemporalHistory::TemporalHistory(const TemporalSettings& settings) : settings_(settings) { settings_.validate(); }

void TemporalHistory::start_over_unless_like(const cl::Context& context, const CameraArgs& camera) {
  if (camera_ && context_() == context() && camera_->width == camera.width && camera_->height == camera.height) return;
  const std::size_t pixels = std::size_t(camera.width) * std::size_t(camera.height);
  context_ = context;
  camera_.reset();
  for (cl::Buffer* buffer : {&ao_, &variance_, &next_ao_, &next_variance_})
    *buffer = cl::Buffer(context, CL_MEM_READ_WRITE, pixels * sizeof(cl_float));
  for (cl::Buffer* buffer : {&length_, &next_length_})
    *buffer = cl::Buffer(context, CL_MEM_READ_WRITE, pixels * sizeof(cl_uint));
  gbuffer_ = cl::Buffer();
}

void TemporalHistory::enqueue_accumulate(cl::CommandQueue& queue, const cl::Context& context,
                                         const cl::Program& program, const FrameBuffers& frame,
                                         const CameraArgs& camera, std::size_t work_group_size) {
  start_over_unless_like(context, camera);
  cl::Kernel kernel(program, "temporal_accumulate");
  const CameraArgs& previous = camera_ ? *camera_ : camera;  // not read without history
  set_kernel_args(kernel, frame.gbuffer, frame.ao, frame.ao_variance, cl_uint(camera_.has_value()), gbuffer_, ao_,
                  variance_, length_, previous, cl_uint(settings_.max_length), next_ao_, next_variance_, next_length_);
  const std::size_t pixels = std::size_t(camera.width) * std::size_t(camera.height);
  launch(queue, kernel, pixels, work_group_size_for(kernel, queue.getInfo<CL_QUEUE_DEVICE>(), work_group_size));
  std::swap(ao_, next_ao_);
  std::swap(variance_, next_variance_);
  std::swap(length_, next_length_);
  gbuffer_ = frame.gbuffer;  // a handle: the buffer outlives the frame that made it
  camera_ = camera;
}

void TemporalHistory::enqueue_read_lengths(cl::CommandQueue& queue, std::vector<cl_uint>& lengths) const {
  read_buffer(queue, length_, false, 0, lengths.size() * sizeof(cl_uint), lengths.data());
}

}  // namespace mbao
