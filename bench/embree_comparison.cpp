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
  if (const char* count = std::getenv("POCL_MAX_PTHREAD_COUNT"); count && std::atoi(count) > 0)
    return unsigned(std::atoi(count));
  return std::max(1u, std::thread::hardware_concurrency());
}

// Frame times of one tracer, with the rays of a frame.
struct Frames {
  std::vector<double> ms;
  std::uint64_t rays_primary = 0, rays_secondary = 0;

  void add(double frame_ms, std::uint64_t primary, std::uint64_t secondary) {
    ms.push_back(frame_ms);
    rays_primary = primary;
    rays_secondary = secondary;
  }
  json to_json() const {
    const double frame_ms = median(ms);
    return {{"frame_ms", frame_ms},
            {"frame_ms_all", ms},
            {"rays_primary", rays_primary},
            {"rays_secondary", rays_secondary},
            {"mrays_per_s", double(rays_primary + rays_secondary) / frame_ms / 1e3}};
  }
};

// mbao, Embree's single rays and Embree's packets in turn, each timed frame
// after an untimed one of the same tracer: a machine whose speed drifts from
// one minute to the next slows all three alike, so the ratio of rays/s stays
// the ratio of the tracers (the development machine once ran Sponza's mbao
// frame in 0.65 of the time it had taken a few minutes before), and every
// timed frame starts on the caches its own tracer filled. Timed frame after
// frame instead, Embree's packets always followed its single rays over the
// same BVH and started warm, while mbao always started on Embree's data.
struct Interleaved {
  Frames mbao, single, packets;
  mbao::RenderStats mbao_stats;  // of the last frame
};

Interleaved interleaved_frames(mbao::Renderer& renderer, const EmbreeAo& embree, const BenchScene& s,
                               const mbao::RenderSettings& settings, int frames) {
  using Mode = EmbreeAo::Mode;
  Interleaved f;
  for (int frame = 0; frame < frames; ++frame) {
    renderer.render(s.scene, s.camera, settings);
    const mbao::RenderStats stats = renderer.render(s.scene, s.camera, settings).stats;
    embree.render(s.camera, settings, Mode::SingleRays);
    const EmbreeFrame single = embree.render(s.camera, settings, Mode::SingleRays);
    embree.render(s.camera, settings, Mode::Packets16);
    const EmbreeFrame packets = embree.render(s.camera, settings, Mode::Packets16);
    f.mbao.add(stats.frame_ms, stats.rays_primary, stats.rays_secondary);
    f.single.add(single.frame_ms, single.rays_primary, single.rays_secondary);
    f.packets.add(packets.frame_ms, packets.rays_primary, packets.rays_secondary);
    f.mbao_stats = stats;
  }
  return f;
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
      const Interleaved f = interleaved_frames(renderer, embree, s, settings, options.frames);
      mbao::RenderSettings counting = settings;
      counting.traversal_stats = true;
      const mbao::RenderStats counted = renderer.render(s.scene, s.camera, counting).stats;
      json mbao_frames = f.mbao.to_json();
      mbao_frames["bounces"] = bounces;
      mbao_frames["memory_bytes"] = f.mbao_stats.memory_bytes;
      mbao_frames["kernel_options"] = f.mbao_stats.kernel_options;
      mbao_frames["organisation"] = f.mbao_stats.organisation;
      mbao_frames["traversal"] = f.mbao_stats.traversal_mode;
      const json single = f.single.to_json(), packets = f.packets.to_json();
      const json& best = single["frame_ms"].get<double>() <= packets["frame_ms"].get<double>() ? single : packets;
      const double ratio = mbao_frames["mrays_per_s"].get<double>() / best["mrays_per_s"].get<double>();
      const json traversal = per_ray_counts(counted);
      std::cout << "| " << s.name << " | " << bounces << " | " << fixed(mbao_frames["frame_ms"], 1) << " | "
                << fixed(single["frame_ms"], 1) << " / " << fixed(packets["frame_ms"], 1) << " | " << fixed(ratio, 2)
                << " | " << fixed(traversal["nodes_per_ray"], 1) << ", " << fixed(traversal["leaves_per_ray"], 1)
                << ", " << fixed(traversal["triangles_per_ray"], 1) << ", " << fixed(traversal["restarts_per_ray"], 2)
                << " |" << std::endl;
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
  std::cout << "\nmbao: traversal " << mbao::to_string(options.settings.traversal)
            << " (the JSON's mbao.traversal and mbao.organisation say what ran); Embree 3: " << threads
            << " threads, high-quality BVH, the faster of its two forms in the ratio; max_distance = inf; a frame of"
               " each of the three in turn, each after an untimed one of its own, medians of "
            << options.frames << ".\n\n";
  return rows;
}

}  // namespace bench
