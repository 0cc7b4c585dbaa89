#include "opencl/command_times.h"

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <optional>
#include <stdexcept>

namespace mbao {
namespace {

// The live CommandTimes by queue, few at a time (one per timed queue): a list is enough.
std::mutex registry_mutex;
std::vector<std::pair<cl_command_queue, CommandTimes*>> registry;

CommandTimes* find(cl_command_queue queue) {
  for (const auto& [timed_queue, times] : registry)
    if (timed_queue == queue) return times;
  return nullptr;
}

// Signed: a driver whose clocks disagree shows as a negative time, not a huge one.
double nanoseconds_to_ms(cl_ulong from, cl_ulong to) { return double(std::int64_t(to - from)) * 1e-6; }

}  // namespace

CommandTimes::CommandTimes(const cl::CommandQueue& queue) : queue_(queue) {
  if (!(queue_.getInfo<CL_QUEUE_PROPERTIES>() & CL_QUEUE_PROFILING_ENABLE))
    throw std::invalid_argument(
        "CommandTimes needs a queue made with CL_QUEUE_PROFILING_ENABLE (a Renderer or ComputeContext with "
        "QueueTiming::On)");
  std::lock_guard<std::mutex> lock(registry_mutex);
  registry.emplace_back(queue_(), this);
}

CommandTimes::~CommandTimes() {
  std::lock_guard<std::mutex> lock(registry_mutex);
  registry.erase(std::find(registry.begin(), registry.end(), std::make_pair(queue_(), this)));
}

bool CommandTimes::timed(const cl::CommandQueue& queue) {
  std::lock_guard<std::mutex> lock(registry_mutex);
  return find(queue()) != nullptr;
}

void CommandTimes::record(const cl::CommandQueue& queue, std::string command, const cl::Event& event) {
  std::lock_guard<std::mutex> lock(registry_mutex);
  if (CommandTimes* times = find(queue())) times->runs_.emplace_back(std::move(command), event);
}

std::vector<CommandTimes::Total> CommandTimes::take() {
  queue_.finish();
  std::vector<std::pair<std::string, cl::Event>> runs;
  {
    std::lock_guard<std::mutex> lock(registry_mutex);
    runs.swap(runs_);
  }
  std::vector<Total> totals;
  std::optional<cl_ulong> previous_end;
  for (const auto& run : runs) {
    const std::string& command = run.first;
    const cl::Event& event = run.second;
    const cl_ulong start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const cl_ulong end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    const cl_ulong idle_from = previous_end ? *previous_end : event.getProfilingInfo<CL_PROFILING_COMMAND_QUEUED>();
    add(totals, {command, 1, nanoseconds_to_ms(start, end), nanoseconds_to_ms(idle_from, start)});
    previous_end = end;
  }
  return totals;
}

void CommandTimes::add(std::vector<Total>& totals, const Total& total) {
  auto sum = std::find_if(totals.begin(), totals.end(), [&](const Total& t) { return t.command == total.command; });
  if (sum == totals.end()) sum = totals.insert(totals.end(), Total{total.command});
  sum->runs += total.runs;
  sum->device_ms += total.device_ms;
  sum->idle_before_ms += total.idle_before_ms;
}

}  // namespace mbao
