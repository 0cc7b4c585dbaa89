#include <iostream>

#include "bench.h"

namespace bench {

json table1(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options) {
  std::cout << "| scene | triangles | max_distance | build ms | b=1 ms | b=2 ms | b=1 Mrays/s | b=2 Mrays/s | HBAO ms "
               "| of which G-buffer ms | HBAO / b=1 | device |\n"
            << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  json rows = json::array();
  for (const BenchScene& s : scenes) {
    const mbao::KdTreeStats tree = s.scene->kd_tree()->stats;
    for (float radius : distance_limits(s)) {
      mbao::RenderSettings settings = options.settings;
      settings.max_distance = radius;
      json row = {{"scene", s.name},
                  {"triangles", s.scene->mesh().triangles.size()},
                  {"masked_triangles", s.scene->masks().triangles.size()},
                  {"max_distance", distance_json(radius)},
                  {"build_ms", tree.build_ms},
                  {"tree", tree_stats_json(tree)},
                  {"frames", json::array()}};
      for (int bounces : {1, 2}) {
        settings.bounces = bounces;
        row["frames"].push_back(measure_frames(renderer, s, settings, options.frames));
      }
      row["hbao"] = measure_frames(renderer, s, hbao_settings(options.settings, radius), options.frames);
      const json& b1 = row["frames"][0];
      const json& b2 = row["frames"][1];
      const json& hbao = row["hbao"];
      std::cout << "| " << s.name << " | " << s.scene->mesh().triangles.size() << " | " << distance_text(radius)
                << " | " << fixed(tree.build_ms, 1) << " | " << fixed(b1["frame_ms"], 1) << " | "
                << fixed(b2["frame_ms"], 1) << " | " << fixed(b1["mrays_per_s"], 1) << " | "
                << fixed(b2["mrays_per_s"], 1) << " | " << fixed(hbao["frame_ms"], 1) << " | "
                << fixed(hbao["gbuffer_ms"], 1) << " | "
                << fixed(hbao["frame_ms"].get<double>() / b1["frame_ms"].get<double>(), 2) << " | "
                << renderer.device().name << " |" << std::endl;
      rows.push_back(row);
    }
  }
  std::cout << "\n"
            << options.settings.width << "x" << options.settings.height << ", r=" << options.settings.samples
            << ", branching, rho=1, spp=1; frame = median of " << options.frames
            << " (camera rays + AO + read-back); Mrays/s counts primary and secondary rays. HBAO (the paper's SSAO "
               "column): 8 directions x 6 steps with the row's radius (inf: the scene's, a quarter of its "
               "diagonal), its frame the G-buffer's camera rays, the HBAO pass and read-back.\n\n";
  return rows;
}

}  // namespace bench
