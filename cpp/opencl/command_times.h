#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "opencl/opencl.h"

namespace mbao {

// The device time of the commands that one queue runs, by command (a kernel by
// its name, every read-back as "read-back", every fill as "fill"), and the
// device's idle time before each, from OpenCL's profiling events: where a
// frame's time goes (mbao_bench's profile section). While it lives,
// every launch, read-back and fill on its queue through opencl/launch.h keeps
// an event for it; the queue must have been made with CL_QUEUE_PROFILING_ENABLE
// (ComputeContext with QueueTiming::On). It registers itself with its queue
// rather than being an argument of every launch: the launch helpers take the
// queue alone, and timing observes a render without being one of its settings.
class CommandTimes {
 public:
  struct Total {
    std::string command;
    std::size_t runs = 0;
    double device_ms = 0.0;  // the runs' start-to-end times, summed
    // From the end of the run before each run on the queue (for the first run
    // since the last take, from its queueing) to its start, summed: the time
    // the device waited for it, for the host to enqueue it, the driver to
    // launch it or memory to be made ready. On an in-order queue the device
    // ran the runs one after the other, so the runs' device and idle times
    // add up to the time from the first one's queueing to the last one's end.
    double idle_before_ms = 0.0;
  };

  // Throws std::invalid_argument for a queue that does not record when its commands ran.
  explicit CommandTimes(const cl::CommandQueue& queue);
  ~CommandTimes();
  CommandTimes(const CommandTimes&) = delete;
  CommandTimes& operator=(const CommandTimes&) = delete;

  // Keeps `event` of a run of `command` where `queue` is timed; does nothing elsewhere.
  static void record(const cl::CommandQueue& queue, std::string command, const cl::Event& event);
  // Whether commands on `queue` should keep their events.
  static bool timed(const cl::CommandQueue& queue);

  // The runs since the last take, summed by command in the order of their
  // first run; waits for them to finish.
  std::vector<Total> take();

  // Adds `total` into the entry of its command in `totals`, a new last entry
  // where there is none: sums by command in the order of their first run.
  static void add(std::vector<Total>& totals, const Total& total);

 private:
  cl::CommandQueue queue_;
  std::vector<std::pair<std::string, cl::Event>> runs_;
};

}  // namespace mbao
