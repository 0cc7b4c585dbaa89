// What specializing the kernels costs and saves: the alpha-mask path on a
// scene without masks, and building kernels with and without warm caches.
#include <unistd.h>

#include <filesystem>
#include <iostream>

#include "bench.h"
#include "opencl/devices.h"
#include "scene/cornell_box.h"

namespace bench {
namespace {

// The Cornell box with a mask table that masks none of its triangles: its
// kernels get the mask path, and every hit pays the lookup.
std::shared_ptr<mbao::Scene> cornell_with_mask_path() {
  const auto cornell = mbao::cornell_box();
  mbao::AlphaMasks masks;
  masks.textures.push_back(MaskTexture{0, 1, 1, 0, 1.0f, 0.5f, {0, 0}});
  masks.texels.push_back(255);
  masks.triangles.push_back(MaskedTriangle{{0, 0, 0, 0, 0, 0}, 0, 0});
  masks.triangle_mask.assign(cornell->mesh().triangles.size(), MBAO_NOT_MASKED);
  return std::make_shared<mbao::Scene>(cornell->mesh(), "cornell_box (mask path)", cornell->camera(),
                                       std::vector<std::string>{}, std::move(masks));
}

}  // namespace

json mask_overhead(mbao::Renderer& renderer, const Options& options) {
  const auto plain = mbao::cornell_box();
  const auto masked = cornell_with_mask_path();
  std::cout << "| Cornell box | kernels without masks, ms | kernels with the mask path, ms | ratio | spread of each |\n"
            << "|---|---:|---:|---:|---|\n";
  json rows = json::array();
  for (int bounces : {1, 2}) {
    mbao::RenderSettings settings = options.settings;
    settings.bounces = bounces;
    renderer.render(plain, *plain->camera(), settings);
    renderer.render(masked, *masked->camera(), settings);
    std::vector<double> without, with;  // interleaved, so drift hits both alike
    for (int f = 0; f < options.frames; ++f) {
      without.push_back(renderer.render(plain, *plain->camera(), settings).stats.frame_ms);
      with.push_back(renderer.render(masked, *masked->camera(), settings).stats.frame_ms);
    }
    const auto [without_lo, without_hi] = std::minmax_element(without.begin(), without.end());
    const auto [with_lo, with_hi] = std::minmax_element(with.begin(), with.end());
    std::cout << "| b=" << bounces << " | " << fixed(median(without), 1) << " | " << fixed(median(with), 1) << " | "
              << fixed(median(with) / median(without), 3) << " | " << fixed(*without_lo, 1) << "-"
              << fixed(*without_hi, 1) << " / " << fixed(*with_lo, 1) << "-" << fixed(*with_hi, 1) << " |\n";
    rows.push_back({{"bounces", bounces}, {"without_masks_ms", without}, {"with_mask_path_ms", with}});
  }
  std::cout << "\n";
  return rows;
}

json kernel_builds(const Options& options) {
  const std::filesystem::path caches =
      std::filesystem::temp_directory_path() / ("mbao-bench-caches-" + std::to_string(::getpid()));
  // The OpenCL drivers' own caches (PoCL's, NVIDIA's) go to the fresh folder too.
  const std::string command = "MBAO_CACHE_DIR=" + shell_quoted((caches / "mbao").string()) +
                              " POCL_CACHE_DIR=" + shell_quoted((caches / "pocl").string()) +
                              " CUDA_CACHE_PATH=" + shell_quoted((caches / "cuda").string()) + " " +
                              shell_quoted(options.self) + " --child-build-kernels " +
                              shell_quoted(options.device.empty() ? "default" : options.device);
  const json cold = run_child(command);
  const json warm = run_child(command);
  std::filesystem::remove_all(caches);
  std::cout << "| a 512x512 Cornell box render in a new process | kernels ms | from | its frame ms |\n"
            << "|---|---:|---|---:|\n";
  for (const auto& [name, run] : {std::pair{"cold (empty caches)", cold}, std::pair{"warm (second process)", warm}})
    std::cout << "| " << name << " | " << fixed(run["kernel_build_ms"], 1) << " | "
              << run["kernel_cache"].get<std::string>() << " | " << fixed(run["frame_ms"], 1) << " |\n";
  std::cout << "\n";
  return {{"cold", cold}, {"warm", warm}};
}

int child_build_kernels(const std::string& device) {
  const mbao::DeviceInfo info = device == "default" ? mbao::default_device() : mbao::find_device(device);
  const auto cornell = mbao::cornell_box();
  mbao::RenderSettings settings;  // Table 1's size: one tile, wider than a grid PoCL builds apart (launch_empty)
  const mbao::RenderStats stats = mbao::Renderer::for_device(info).render(cornell, *cornell->camera(), settings).stats;
  std::cout << json{{"kernel_build_ms", stats.kernel_build_ms},
                    {"kernel_cache", stats.kernel_cache},
                    {"frame_ms", stats.frame_ms}}
                   .dump()
            << "\n";
  return 0;
}

}  // namespace bench
