// Where a frame's time goes: each command's device time and the device's idle
// time before it, from OpenCL's profiling events, beside the frame's wall time.
// What they leave of the frame is the host's, before its first command was
// queued and after its last one ended.
#include <iostream>
#include <limits>
#include <numeric>

#include "bench.h"
#include "opencl/command_times.h"

namespace bench {
namespace {

struct Workload {
  std::string name;
  mbao::RenderSettings settings;
};

// Table 1's frames at max_distance = inf, and HBAO's at the scene's radius.
std::vector<Workload> workloads(const Options& options) {
  mbao::RenderSettings b1 = options.settings, b2 = options.settings;
  b1.bounces = 1;
  b2.bounces = 2;
  return {{"b=1", b1}, {"b=2", b2}, {"HBAO", hbao_settings(options.settings, std::numeric_limits<float>::infinity())}};
}

// The frames' mean wall time, and each command's runs, device time and idle
// time before it per frame, means over the same frames, after one frame that
// builds and uploads. Taken frame by frame, so that no idle time spans two.
json profile_frames(mbao::Renderer& renderer, mbao::CommandTimes& times, const BenchScene& scene,
                    const mbao::RenderSettings& settings, int frames) {
  renderer.render(scene.scene, scene.camera, settings);
  times.take();
  std::vector<double> wall;
  std::vector<mbao::CommandTimes::Total> sums;  // by command, in the order of their first run
  for (int f = 0; f < frames; ++f) {
    wall.push_back(renderer.render(scene.scene, scene.camera, settings).stats.frame_ms);
    for (const mbao::CommandTimes::Total& total : times.take()) mbao::CommandTimes::add(sums, total);
  }
  json commands = json::array();
  for (const mbao::CommandTimes::Total& sum : sums)
    commands.push_back({{"command", sum.command},
                        {"runs_per_frame", double(sum.runs) / frames},
                        {"device_ms_per_frame", sum.device_ms / frames},
                        {"idle_before_ms_per_frame", sum.idle_before_ms / frames}});
  const double mean_ms = std::accumulate(wall.begin(), wall.end(), 0.0) / double(frames);
  return {{"frame_ms", mean_ms}, {"frame_ms_all", wall}, {"commands", commands}};
}

}  // namespace

json profile(const mbao::DeviceInfo& device, const std::vector<BenchScene>& scenes, const Options& options) {
  // A renderer of the section's own: only its queue records when commands ran.
  mbao::Renderer renderer(device, mbao::QueueTiming::On);
  mbao::CommandTimes times(renderer.queue());
  std::cout << "| scene | frame | frame ms | command | runs | device ms | idle before ms | of the frame |\n"
            << "|---|---|---:|---|---:|---:|---:|---:|\n";
  json rows = json::array();
  for (const BenchScene& s : scenes) {
    for (const Workload& workload : workloads(options)) {
      const json frames = profile_frames(renderer, times, s, workload.settings, options.frames);
      const double frame_ms = frames["frame_ms"];
      double span_ms = 0.0;  // from the first command's queueing to the last one's end
      for (const json& command : frames["commands"]) {
        const double ms = command["device_ms_per_frame"], idle_ms = command["idle_before_ms_per_frame"];
        span_ms += ms + idle_ms;
        std::cout << "| " << s.name << " | " << workload.name << " | " << fixed(frame_ms, 2) << " | "
                  << command["command"].get<std::string>() << " | " << fixed(command["runs_per_frame"], 1) << " | "
                  << fixed(ms, 3) << " | " << fixed(idle_ms, 3) << " | " << fixed((ms + idle_ms) / frame_ms, 2)
                  << " |\n";
      }
      std::cout << "| " << s.name << " | " << workload.name << " | " << fixed(frame_ms, 2)
                << " | (the host, before the first command and after the last) | | " << fixed(frame_ms - span_ms, 3)
                << " | | " << fixed((frame_ms - span_ms) / frame_ms, 2) << " |" << std::endl;
      rows.push_back({{"scene", s.name}, {"frame", workload.name}, {"frames", frames}});
    }
  }
  std::cout << "\nThe Table 1 workload at max_distance = inf, and HBAO at the scene's radius; frame ms, each "
               "command's device ms and the device's idle ms before it (OpenCL's profiling events) are means over "
            << options.frames << " frames.\n\n";
  return rows;
}

}  // namespace bench
