// The four kd traversals on the same frames: time and what each ray costs.
#include <iostream>

#include "bench.h"

namespace bench {
namespace {

constexpr mbao::Traversal kTraversals[] = {mbao::Traversal::Restart, mbao::Traversal::PushDown,
                                           mbao::Traversal::ShortStack, mbao::Traversal::Stack};

}  // namespace

json traversals(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options) {
  std::cout << "| scene | traversal | b=2 ms | per ray: nodes | leaves | triangle tests | restarts |\n"
            << "|---|---|---:|---:|---:|---:|---:|\n";
  json rows = json::array();
  for (const BenchScene& s : scenes) {
    mbao::RenderSettings settings = options.settings;
    settings.bounces = 2;
    for (mbao::Traversal traversal : kTraversals) {
      settings.traversal = traversal;
      settings.count_traversal = false;
      const json frames = measure_frames(renderer, s, settings, options.frames);
      settings.count_traversal = true;
      const json counts = per_ray_counts(renderer.render(s.scene, s.camera, settings).stats);
      std::cout << "| " << s.name << " | " << mbao::to_string(traversal) << " | " << fixed(frames["frame_ms"], 1)
                << " | " << fixed(counts["nodes_per_ray"], 1) << " | " << fixed(counts["leaves_per_ray"], 1) << " | "
                << fixed(counts["triangles_per_ray"], 1) << " | " << fixed(counts["restarts_per_ray"], 2) << " |"
                << std::endl;
      rows.push_back({{"scene", s.name}, {"traversal", mbao::to_string(traversal)}, {"frames", frames}, {"per_ray", counts}});
    }
  }
  std::cout << "\nTable 1 configuration at b = 2, max_distance = inf; counts from a second, counting build.\n\n";
  return rows;
}

}  // namespace bench
