#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "bench.h"

namespace bench {

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

std::vector<float> distance_limits(const BenchScene& scene) {
  std::vector<float> limits = {std::numeric_limits<float>::infinity()};
  if (scene.camera.max_distance) limits.push_back(*scene.camera.max_distance);
  return limits;
}

mbao::RenderSettings hbao_settings(const mbao::RenderSettings& row, float radius) {
  mbao::RenderSettings s = row;
  s.method = mbao::Method::Hbao;
  s.bounces = 1;
  s.max_distance = std::isinf(radius) ? std::nullopt : std::optional<float>(radius);
  return s;
}

json distance_json(float max_distance) { return std::isinf(max_distance) ? json("inf") : json(max_distance); }

std::string distance_text(float max_distance) {
  return std::isinf(max_distance) ? std::string("inf") : fixed(max_distance, 1);
}

json tree_stats_json(const mbao::KdTreeStats& tree) {
  return {{"nodes", tree.nodes},
          {"leaves", tree.leaves},
          {"empty_leaves", tree.empty_leaves},
          {"max_depth", tree.max_depth},
          {"mean_triangles_per_leaf", tree.mean_triangles_per_leaf},
          {"leaf_references", tree.leaf_references},
          {"sah_cost", tree.sah_cost},
          {"memory_bytes", tree.memory_bytes}};
}

json per_ray_counts(const mbao::RenderStats& counted) {
  const double rays = double(counted.rays_primary + counted.rays_secondary);
  return {{"nodes_per_ray", double(counted.traversal->nodes) / rays},
          {"leaves_per_ray", double(counted.traversal->leaves) / rays},
          {"triangles_per_ray", double(counted.traversal->triangles) / rays},
          {"restarts_per_ray", double(counted.traversal->restarts) / rays}};
}

json measure_frames(mbao::Renderer& renderer, const BenchScene& scene, const mbao::RenderSettings& settings,
                    int frames) {
  renderer.render(scene.scene, scene.camera, settings);
  std::vector<double> times, gbuffer_times;
  mbao::RenderStats stats;
  for (int f = 0; f < frames; ++f) {
    const mbao::RenderResult result = renderer.render(scene.scene, scene.camera, settings);
    times.push_back(result.stats.frame_ms);
    gbuffer_times.push_back(result.stats.gbuffer_ms);
    stats = result.stats;
  }
  const double frame_ms = median(times);
  const double rays = double(stats.rays_primary + stats.rays_secondary);
  if (settings.method == mbao::Method::Hbao)
    return {{"frame_ms", frame_ms},
            {"frame_ms_all", times},
            {"gbuffer_ms", median(gbuffer_times)},
            {"max_distance", stats.max_distance},
            {"directions", settings.hbao.directions},
            {"steps", settings.hbao.steps},
            {"traversal", stats.traversal_mode},
            {"memory_bytes", stats.memory_bytes}};
  return {{"bounces", settings.bounces},
          {"frame_ms", frame_ms},
          {"frame_ms_all", times},
          {"rays_primary", stats.rays_primary},
          {"rays_secondary", stats.rays_secondary},
          {"mrays_per_s", rays / frame_ms / 1e3},
          {"memory_bytes", stats.memory_bytes},
          {"kernel_options", stats.kernel_options},
          {"organisation", stats.organisation}};
}

std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

long peak_rss_kb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

json run_child(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run: " + command);
  std::string output, last_line;
  std::array<char, 4096> chunk;
  while (std::fgets(chunk.data(), int(chunk.size()), pipe)) output += chunk.data();
  if (pclose(pipe) != 0) throw std::runtime_error("failed: " + command + "\n" + output);
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);)
    if (!line.empty()) last_line = line;
  return json::parse(last_line);
}

}  // namespace bench
