// mbao on its OpenCL device beside Embree 3 on the CPU, on the same workload.
#include <cstdlib>
#include <iostream>
#include <thread>

#include "bench.h"
#include "embree_ao.h"

namespace bench {
namespace {

// PoCL runs one thread per core unless POCL_MAX_PTHREAD_COUNT says otherwise; Embree gets as many.
unsigned pocl_threads() {
  if (const char* count = std::getenv("POCL_MAX_PTHREAD_COUNT"); count && std::atoi(count) > 0) return unsigned(std::atoi(count));
  return std::max(1u, std::thread::hardware_concurrency());
}

json embree_frames(const EmbreeAo& embree, const BenchScene& s, const mbao::RenderSettings& settings, int frames,
                   EmbreeAo::Mode mode) {
  embree.render(s.camera, settings, mode);  // warm-up, as for mbao
  std::vector<double> times;
  EmbreeFrame frame;
  for (int f = 0; f < frames; ++f) {
    frame = embree.render(s.camera, settings, mode);
    times.push_back(frame.frame_ms);
  }
  const double frame_ms = median(times);
  return {{"frame_ms", frame_ms},
          {"frame_ms_all", times},
          {"rays_primary", frame.rays_primary},
          {"rays_secondary", frame.rays_secondary},
          {"mrays_per_s", double(frame.rays_primary + frame.rays_secondary) / frame_ms / 1e3}};
}

}  // namespace

json embree_comparison(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options) {
  const unsigned threads = pocl_threads();
  std::cout << "| scene | b | mbao ms | Embree ms (single rays / packets of 16) | rays/s mbao / Embree | "
               "per ray: nodes, leaves, triangle tests, restarts |\n|---|---:|---:|---:|---:|---|\n";
  json rows = json::array();
  for (const BenchScene& s : scenes) {
    const EmbreeAo embree(s.scene, threads);
    for (int bounces : {1, 2}) {
      mbao::RenderSettings settings = options.settings;
      settings.bounces = bounces;
      const json mbao_frames = measure_frames(renderer, s, settings, options.frames);
      mbao::RenderSettings counting = settings;
      counting.count_traversal = true;
      const mbao::RenderStats counted = renderer.render(s.scene, s.camera, counting).stats;
      const json single = embree_frames(embree, s, settings, options.frames, EmbreeAo::Mode::SingleRays);
      const json packets = embree_frames(embree, s, settings, options.frames, EmbreeAo::Mode::Packets16);
      const json& best = single["frame_ms"].get<double>() <= packets["frame_ms"].get<double>() ? single : packets;
      const double ratio = mbao_frames["mrays_per_s"].get<double>() / best["mrays_per_s"].get<double>();
      const json traversal = per_ray_counts(counted);
      std::cout << "| " << s.name << " | " << bounces << " | " << fixed(mbao_frames["frame_ms"], 1) << " | "
                << fixed(single["frame_ms"], 1) << " / " << fixed(packets["frame_ms"], 1) << " | " << fixed(ratio, 2)
                << " | " << fixed(traversal["nodes_per_ray"], 1) << ", " << fixed(traversal["leaves_per_ray"], 1) << ", "
                << fixed(traversal["triangles_per_ray"], 1) << ", " << fixed(traversal["restarts_per_ray"], 2) << " |"
                << std::endl;
      rows.push_back({{"scene", s.name},
                      {"bounces", bounces},
                      {"mbao", mbao_frames},
                      {"traversal", traversal},
                      {"embree_threads", threads},
                      {"embree_build_ms", embree.build_ms()},
                      {"embree_single_rays", single},
                      {"embree_packets16", packets},
                      {"rays_per_s_ratio", ratio}});
    }
  }
  std::cout << "\nmbao: " << mbao::to_string(options.settings.traversal) << " traversal; Embree 3: " << threads
            << " threads, high-quality BVH, the faster of its two forms in the ratio; max_distance = inf.\n\n";
  return rows;
}

}  // namespace bench
