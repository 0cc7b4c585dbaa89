// Growth with the scene's size: generated scenes of unit UV spheres on a grid
// (32 rings x 64 segments, 3968 triangles each) of about 1M, 4M, 8.4M (the
// issue's scene), 16M and 32M triangles (--scale-sizes), each in a process of
// its own: the kd-tree's build, a frame (b = 1, radius 1, the Table 1 size) and
// the process's peak memory once it has built the tree and once it has also
// rendered. Where the benchmark has Embree, once the peak is read: rounds
// of mbao's build and Embree's BVH builds of the same triangles (high
// quality, all threads; robust and not), a ratio to each, the median of the
// rounds' ratios.
#include <cmath>
#include <iostream>
#include <thread>

#include "bench.h"
#include "core/timer.h"
#ifdef MBAO_BENCH_EMBREE
#include "embree_ao.h"
#endif

namespace bench {
namespace {

constexpr int kRings = 32, kSegments = 64;

// About `triangles` triangles of spheres 3 apart on a cube's grid, as a loader hands them over.
mbao::TriangleMesh spheres(std::size_t triangles) {
  const std::size_t per_sphere = std::size_t(2 * kSegments * (kRings - 1));
  const std::size_t count = std::max<std::size_t>(1, triangles / per_sphere);
  const auto side = std::size_t(std::ceil(std::cbrt(double(count))));
  mbao::TriangleMesh mesh;
  mesh.positions.reserve(count * std::size_t(kSegments * (kRings - 1) + 2));
  mesh.triangles.reserve(count * per_sphere);
  for (std::size_t k = 0; k < count; ++k) {
    const glm::vec3 centre(3.0f * float(k % side), 3.0f * float(k / side % side), 3.0f * float(k / side / side));
    const auto top = std::uint32_t(mesh.positions.size());
    mesh.positions.push_back(centre + glm::vec3(0.0f, 1.0f, 0.0f));
    for (int r = 1; r < kRings; ++r)
      for (int s = 0; s < kSegments; ++s) {
        const float theta = 3.14159265f * float(r) / kRings, phi = 6.28318531f * float(s) / kSegments;
        mesh.positions.push_back(
            centre + glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
      }
    const auto bottom = std::uint32_t(mesh.positions.size());
    mesh.positions.push_back(centre + glm::vec3(0.0f, -1.0f, 0.0f));
    const auto ring = [&](int r, int s) { return top + 1u + std::uint32_t(r * kSegments + s % kSegments); };
    for (int s = 0; s < kSegments; ++s) mesh.triangles.push_back({top, ring(0, s + 1), ring(0, s)});
    for (int r = 0; r + 2 < kRings; ++r)
      for (int s = 0; s < kSegments; ++s) {
        mesh.triangles.push_back({ring(r, s), ring(r, s + 1), ring(r + 1, s + 1)});
        mesh.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r + 1, s)});
      }
    for (int s = 0; s < kSegments; ++s)
      mesh.triangles.push_back({bottom, ring(kRings - 2, s), ring(kRings - 2, s + 1)});
  }
  return mesh;
}

#ifdef MBAO_BENCH_EMBREE
// The build ratios come from rounds, each building mbao's tree again (from
// the scene's mesh and origin: the same tree, which is checked) and Embree's
// two BVHs in turn: this machine's speed drifts by more than a change being
// measured, and within a round the drift reaches all three builds alike.
constexpr int kBuildRounds = 3;

// One rebuild of the scene's tree, timed alone.
double rebuild_ms(const mbao::Scene& scene, const mbao::KdTreeStats& built) {
  const mbao::Stopwatch clock;
  const mbao::KdTree tree = mbao::build_kd_tree(scene.mesh(), mbao::KdBuildOptions{}, scene.render_origin());
  const double ms = clock.elapsed_ms();
  if (tree.stats.nodes != built.nodes || tree.stats.leaf_references != built.leaf_references)
    throw std::runtime_error("scale: a rebuild of the kd-tree differs from the scene's");
  return ms;
}

// The rounds, and their medians in `row`: each build's time and each ratio.
void build_rounds(const std::shared_ptr<const mbao::Scene>& scene, const mbao::KdTreeStats& built, json& row) {
  const unsigned threads = std::thread::hardware_concurrency();
  json rounds = json::array();
  std::vector<double> mbao_ms, robust_ms, not_robust_ms, ratios, not_robust_ratios;
  for (int round = 0; round < kBuildRounds; ++round) {
    mbao_ms.push_back(rebuild_ms(*scene, built));
    not_robust_ms.push_back(EmbreeAo(scene, threads, false).build_ms());
    robust_ms.push_back(EmbreeAo(scene, threads, true).build_ms());
    ratios.push_back(mbao_ms.back() / robust_ms.back());
    not_robust_ratios.push_back(mbao_ms.back() / not_robust_ms.back());
    rounds.push_back({{"build_ms", mbao_ms.back()},
                      {"embree_build_ms", robust_ms.back()},
                      {"embree_not_robust_build_ms", not_robust_ms.back()}});
  }
  row["rounds"] = rounds;
  row["rounds_build_ms"] = median(mbao_ms);
  row["embree_build_ms"] = median(robust_ms);
  row["embree_not_robust_build_ms"] = median(not_robust_ms);
  row["build_ratio"] = median(ratios);
  row["build_ratio_not_robust"] = median(not_robust_ratios);
}
#endif

}  // namespace

int child_scale(std::size_t triangles, const mbao::DeviceInfo& device, int width, int height) {
  const mbao::Stopwatch make_clock;
  auto scene = std::make_shared<mbao::Scene>(spheres(triangles), "spheres");
  const double make_ms = make_clock.elapsed_ms();
  const mbao::Stopwatch build_clock;
  const mbao::KdTreeStats tree = scene->kd_tree()->stats;
  const double build_ms = build_clock.elapsed_ms();
  const long build_peak_kb = peak_rss_kb();
  mbao::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.bounces = 1;
  settings.max_distance = 1.0f;
  mbao::Renderer& renderer = mbao::Renderer::for_device(device);
  const mbao::Camera camera = mbao::Camera::framing(scene->bounds(), float(width) / float(height));
  renderer.render(scene, camera, settings);  // the upload and the kernels' build
  const double frame_ms = renderer.render(scene, camera, settings).stats.frame_ms;
  const long peak_kb = peak_rss_kb();
  const std::size_t count = scene->mesh().triangles.size();
  const auto per_triangle = [count](long kb) { return double(kb) * 1024.0 / double(count); };
  json row = {{"triangles", count},
              {"make_ms", make_ms},
              {"build_ms", build_ms},
              {"frame_ms", frame_ms},
              {"build_peak_rss_kb", build_peak_kb},
              {"build_peak_bytes_per_triangle", per_triangle(build_peak_kb)},
              {"peak_rss_kb", peak_kb},
              {"peak_bytes_per_triangle", per_triangle(peak_kb)},
              {"tree", tree_stats_json(tree)}};
#ifdef MBAO_BENCH_EMBREE
  build_rounds(scene, tree, row);
#endif
  std::cout << row.dump() << "\n";
  return 0;
}

json scale(const Options& options) {
  std::cout << "| triangles | mbao build ms | Embree build ms | build ratio | Embree build ms, not robust "
               "| build ratio, not robust | frame ms | peak bytes per triangle, built | peak MiB, rendered "
               "| peak bytes per triangle, rendered |\n"
               "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  const auto cell = [](const json& row, const char* key, int digits) {
    return row.contains(key) ? fixed(row[key], digits) : std::string();
  };
  json rows = json::array();
  for (const std::size_t size : options.scale_sizes) {
    const json row = run_child(shell_quoted(options.self) + " --child-scale " + std::to_string(size) + " " +
                               shell_quoted(options.device.empty() ? "-" : options.device) + " " +
                               std::to_string(options.settings.width) + " " + std::to_string(options.settings.height));
    const bool embree = row.contains("rounds");
    std::cout << "| " << row["triangles"] << " | " << fixed(row[embree ? "rounds_build_ms" : "build_ms"], 0) << " | "
              << cell(row, "embree_build_ms", 0) << " | " << cell(row, "build_ratio", 2) << " | "
              << cell(row, "embree_not_robust_build_ms", 0) << " | " << cell(row, "build_ratio_not_robust", 2) << " | "
              << fixed(row["frame_ms"], 1) << " | " << fixed(row["build_peak_bytes_per_triangle"], 0) << " | "
              << fixed(row["peak_rss_kb"].get<double>() / 1024.0, 0) << " | "
              << fixed(row["peak_bytes_per_triangle"], 0) << " |" << std::endl;
    rows.push_back(row);
  }
  std::cout << "\nEach size in a fresh process; peak = its maximum resident set size once the tree is built, and"
               " once two frames (b = 1, radius 1) are rendered too.";
#ifdef MBAO_BENCH_EMBREE
  std::cout << " Build times and ratios: medians of " << kBuildRounds << " rounds of the three builds.";
#endif
  std::cout << "\n\n";
  return rows;
}

}  // namespace bench
