#include "opencl/launch.h"

#include "opencl/command_times.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace mbao {
namespace {

// Every command of a frame goes through here, so that a timed queue
// (opencl/command_times.h) sees them all: enqueue(event) enqueues it, with an
// event where the queue is timed, which is kept under name().
template <class Enqueue, class Name>
void enqueue_seen(cl::CommandQueue& queue, const Enqueue& enqueue, const Name& name) {
  if (!CommandTimes::timed(queue)) {
    enqueue(nullptr);
    return;
  }
  cl::Event event;
  enqueue(&event);
  CommandTimes::record(queue, name(), event);
}

void enqueue(cl::CommandQueue& queue, const cl::Kernel& kernel, const cl::NDRange& global, const cl::NDRange& local) {
  const auto run = [&](cl::Event* event) {
    queue.enqueueNDRangeKernel(kernel, cl::NullRange, global, local, nullptr, event);
  };
  enqueue_seen(queue, run, [&] { return kernel.getInfo<CL_KERNEL_FUNCTION_NAME>(); });
}

}  // namespace

std::size_t work_group_size_for(const cl::Kernel& kernel, const cl::Device& device, std::size_t requested) {
  constexpr std::size_t kDefault = 64;
  const std::size_t limit = kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device);
  if (requested > limit)
    throw std::invalid_argument("work_group_size must be at most " + std::to_string(limit) + " on this device, got " +
                                std::to_string(requested));
  return requested ? requested : std::min(kDefault, limit);
}

void launch(cl::CommandQueue& queue, const cl::Kernel& kernel, std::size_t items, std::size_t work_group) {
  const std::size_t groups = std::max<std::size_t>(1, (items + work_group - 1) / work_group);
  enqueue(queue, kernel, cl::NDRange(groups * work_group), cl::NDRange(work_group));
}

void launch_rows(cl::CommandQueue& queue, const cl::Kernel& kernel, std::size_t columns, std::size_t rows,
                 std::size_t work_group) {
  const std::size_t groups = std::max<std::size_t>(1, (columns + work_group - 1) / work_group);
  enqueue(queue, kernel, cl::NDRange(groups * work_group, std::max<std::size_t>(1, rows)), cl::NDRange(work_group, 1));
}

void read_buffer(cl::CommandQueue& queue, const cl::Buffer& buffer, bool blocking, std::size_t offset,
                 std::size_t bytes, void* into) {
  const auto read = [&](cl::Event* event) {
    queue.enqueueReadBuffer(buffer, blocking, offset, bytes, into, nullptr, event);
  };
  enqueue_seen(queue, read, [] { return "read-back"; });
}

void zero_words(cl::CommandQueue& queue, const cl::Buffer& buffer, std::size_t count) {
  const auto fill = [&](cl::Event* event) {
    queue.enqueueFillBuffer(buffer, cl_uint(0), 0, count * sizeof(cl_uint), nullptr, event);
  };
  enqueue_seen(queue, fill, [] { return "fill"; });
}

std::size_t rays_per_lane_item(std::size_t rays, const cl::Device& device, std::size_t work_group) {
  constexpr std::size_t kMost = 512, kLeast = 16, kGroupsPerUnit = 4;
  const std::size_t units = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
  const std::size_t items = units * kGroupsPerUnit * work_group;
  return std::clamp((rays + items - 1) / items, kLeast, kMost);
}

void launch_empty(cl::CommandQueue& queue, const cl::Kernel& kernel, std::size_t largest_items,
                  std::size_t work_group) {
  launch(queue, kernel, 0, work_group);
  if (largest_items > work_group) launch(queue, kernel, largest_items, work_group);
}

}  // namespace mbao
