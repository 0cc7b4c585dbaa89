// The AO kernels organised as a megakernel (one work item per pixel runs the
// whole estimator) against the wavefront (one launch per bounce over a queue of
// the surfaces still bouncing), on the Table 1 workload. Both render the same
// image, checked here bit for bit; their frames are measured interleaved, so
// that drift of the machine's speed hits both alike.
#include <algorithm>
#include <cstring>
#include <iostream>

#include "bench.h"

namespace bench {
namespace {

bool same_render(const mbao::RenderResult& a, const mbao::RenderResult& b) {
  return a.ao.size() == b.ao.size() && std::memcmp(a.ao.data(), b.ao.data(), a.ao.size() * sizeof(float)) == 0 &&
         a.coverage == b.coverage && a.stats.rays_secondary == b.stats.rays_secondary;
}

// One untimed render of each (kernel compiles, scene upload, the image check),
// then `frames` of each in turn. The ratio is the median over the frame pairs:
// a pair shares the machine's speed of the moment, which drifts by more than
// the two organisations differ.
json compare(mbao::Renderer& renderer, const BenchScene& s, mbao::RenderSettings settings, int frames) {
  mbao::RenderSettings mega = settings, wave = settings;
  mega.organisation = mbao::KernelOrganisation::Megakernel;
  wave.organisation = mbao::KernelOrganisation::Wavefront;
  const mbao::RenderResult first_mega = renderer.render(s.scene, s.camera, mega);
  const mbao::RenderResult first_wave = renderer.render(s.scene, s.camera, wave);
  std::vector<double> mega_ms, wave_ms, ratios;
  for (int f = 0; f < frames; ++f) {
    mega_ms.push_back(renderer.render(s.scene, s.camera, mega).stats.frame_ms);
    wave_ms.push_back(renderer.render(s.scene, s.camera, wave).stats.frame_ms);
    ratios.push_back(wave_ms.back() / mega_ms.back());
  }
  const auto [ratio_lo, ratio_hi] = std::minmax_element(ratios.begin(), ratios.end());
  return {{"bounces", settings.bounces},
          {"work_group_size", settings.work_group_size},
          {"megakernel_ms", median(mega_ms)},
          {"wavefront_ms", median(wave_ms)},
          {"wavefront_over_megakernel", median(ratios)},
          {"wavefront_over_megakernel_range", {*ratio_lo, *ratio_hi}},
          {"megakernel_ms_all", mega_ms},
          {"wavefront_ms_all", wave_ms},
          {"same_image", same_render(first_mega, first_wave)},
          {"rays_secondary", first_wave.stats.rays_secondary},
          {"megakernel_memory_bytes", first_mega.stats.memory_bytes},
          {"wavefront_memory_bytes", first_wave.stats.memory_bytes},
          {"wavefront_tiles", first_wave.stats.tiles}};
}

std::string group_name(std::size_t work_group_size) {
  return work_group_size ? std::to_string(work_group_size) : "default";
}

}  // namespace

json organisation(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options) {
  std::cout << "| scene | max_distance | b | work group | megakernel ms | wavefront ms | wavefront / megakernel | "
               "range of the pairs | same image |\n|---|---:|---:|---:|---:|---:|---:|---|---|\n";
  json rows = json::array();
  for (std::size_t work_group_size : options.work_groups) {
    for (const BenchScene& s : scenes) {
      for (float radius : distance_limits(s)) {
        for (int bounces : {1, 2}) {
          mbao::RenderSettings settings = options.settings;
          settings.max_distance = radius;
          settings.bounces = bounces;
          settings.work_group_size = work_group_size;
          json row = compare(renderer, s, settings, options.frames);
          row["scene"] = s.name;
          row["max_distance"] = distance_json(radius);
          std::cout << "| " << s.name << " | " << distance_text(radius) << " | " << bounces << " | "
                    << group_name(work_group_size) << " | " << fixed(row["megakernel_ms"], 1) << " | "
                    << fixed(row["wavefront_ms"], 1) << " | " << fixed(row["wavefront_over_megakernel"], 3) << " | "
                    << fixed(row["wavefront_over_megakernel_range"][0], 3) << "-"
                    << fixed(row["wavefront_over_megakernel_range"][1], 3) << " | "
                    << (row["same_image"].get<bool>() ? "yes" : "NO") << " |" << std::endl;
          rows.push_back(row);
        }
      }
    }
  }
  std::cout << "\n"
            << options.settings.width << "x" << options.settings.height << ", r=" << options.settings.samples
            << ", branching, rho=1, spp=1; ms = median of " << options.frames
            << " frames, the two organisations interleaved; wavefront / megakernel = median over the frame pairs;"
               " work group \"default\" = 64 unless a kernel allows less; \"same image\": bit for bit, with the"
               " same ray count.\n\n";
  return rows;
}

}  // namespace bench
