// The kd traversals on the same frames: time and what each ray costs.
#include <iostream>

#include "bench.h"

namespace bench {
namespace {

// The four walks of one ray per work item, then lanes on CPUs only: on a GPU
// sixteen stacks per work item would leave it no room to hide latency.
std::vector<mbao::Traversal> traversals_for(const mbao::DeviceInfo& device) {
  std::vector<mbao::Traversal> traversals = {mbao::Traversal::Restart, mbao::Traversal::PushDown,
                                             mbao::Traversal::ShortStack, mbao::Traversal::Stack};
  if (device.type == "CPU") traversals.push_back(mbao::Traversal::Lanes);
  return traversals;
}

}  // namespace

json traversals(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options) {
  std::cout << "| scene | traversal | b=2 ms | per ray: nodes | leaves | triangle tests | restarts |\n"
            << "|---|---|---:|---:|---:|---:|---:|\n";
  json rows = json::array();
  for (const BenchScene& s : scenes) {
    mbao::RenderSettings settings = options.settings;
    settings.bounces = 2;
    for (mbao::Traversal traversal : traversals_for(renderer.device())) {
      settings.traversal = traversal;
      settings.traversal_stats = false;
      const json frames = measure_frames(renderer, s, settings, options.frames);
      settings.traversal_stats = true;
      const json counts = per_ray_counts(renderer.render(s.scene, s.camera, settings).stats);
      std::cout << "| " << s.name << " | " << mbao::to_string(traversal) << " | " << fixed(frames["frame_ms"], 1)
                << " | " << fixed(counts["nodes_per_ray"], 1) << " | " << fixed(counts["leaves_per_ray"], 1) << " | "
                << fixed(counts["triangles_per_ray"], 1) << " | " << fixed(counts["restarts_per_ray"], 2) << " |"
                << std::endl;
      rows.push_back(
          {{"scene", s.name}, {"traversal", mbao::to_string(traversal)}, {"frames", frames}, {"per_ray", counts}});
    }
  }
  std::cout << "\nTable 1 configuration at b = 2, max_distance = inf, the organisation each traversal runs in by "
               "default; counts from a second, counting build.\n\n";
  return rows;
}

}  // namespace bench
