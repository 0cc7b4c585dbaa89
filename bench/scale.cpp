// Growth with the scene's size: generated scenes of unit UV spheres on a grid
// (32 rings x 64 segments, 3968 triangles each) of about 1M, 4M, 8.4M (the
// issue's scene), 16M and 32M triangles (--scale-sizes), each in a process of
// its own: the kd-tree's build, a frame (b = 1, radius 1, the Table 1 size) and
// the process's peak memory once it has built the tree and once it has also
// rendered, with Embree's BVH build of
// the same triangles (high quality, all threads; robust and not, a ratio to
// each) where the benchmark has Embree, measured after the peak is read.
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
        mesh.positions.push_back(centre + glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                    std::sin(theta) * std::sin(phi)));
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
    for (int s = 0; s < kSegments; ++s) mesh.triangles.push_back({bottom, ring(kRings - 2, s), ring(kRings - 2, s + 1)});
  }
  return mesh;
}

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
  const unsigned threads = std::thread::hardware_concurrency();
  // The build the ratio is to second, when Embree's threads have started.
  row["embree_not_robust_build_ms"] = EmbreeAo(scene, threads, false).build_ms();
  row["embree_build_ms"] = EmbreeAo(scene, threads, true).build_ms();
#endif
  std::cout << row.dump() << "\n";
  return 0;
}

json scale(const Options& options) {
  std::cout << "| triangles | mbao build ms | Embree build ms | build ratio | Embree build ms, not robust "
               "| build ratio, not robust | frame ms | peak bytes per triangle, built | peak MiB, rendered "
               "| peak bytes per triangle, rendered |\n"
               "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  json rows = json::array();
  for (const std::size_t size : options.scale_sizes) {
    const json row = run_child(shell_quoted(options.self) + " --child-scale " + std::to_string(size) + " " +
                               shell_quoted(options.device.empty() ? "-" : options.device) + " " +
                               std::to_string(options.settings.width) + " " + std::to_string(options.settings.height));
    const bool embree = row.contains("embree_build_ms");
    const auto build_ratio = [&](const char* embree_ms) {
      return embree ? fixed(row["build_ms"].get<double>() / row[embree_ms].get<double>(), 2) : std::string();
    };
    std::cout << "| " << row["triangles"] << " | " << fixed(row["build_ms"], 0) << " | "
              << (embree ? fixed(row["embree_build_ms"], 0) : "") << " | " << build_ratio("embree_build_ms")
              << " | " << (embree ? fixed(row["embree_not_robust_build_ms"], 0) : "") << " | "
              << build_ratio("embree_not_robust_build_ms") << " | " << fixed(row["frame_ms"], 1) << " | "
              << fixed(row["build_peak_bytes_per_triangle"], 0) << " | "
              << fixed(row["peak_rss_kb"].get<double>() / 1024.0, 0)
              << " | " << fixed(row["peak_bytes_per_triangle"], 0) << " |" << std::endl;
    rows.push_back(row);
  }
  std::cout << "\nEach size in a fresh process; peak = its maximum resident set size once the tree is built, and"
               " once two frames (b = 1, radius 1) are rendered too.\n\n";
  return rows;
}

}  // namespace bench
