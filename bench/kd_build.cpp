// The kd-tree build: clipping straddling triangles everywhere ("perfect
// splits") against the default, which clips only in the larger nodes, and the
// default with every plane of the SAH sweep priced (the same tree, built
// without the sweep's pruning). Build time (interleaved, all threads), the
// trees, and what the trees cost the Table 1 workload's rays.
#include <iostream>

#include "bench.h"

namespace bench {
namespace {

struct Variant {
  std::string name;
  mbao::KdBuildOptions options;
};

// The default first: the others' build times are compared with it.
std::vector<Variant> variants() {
  const mbao::KdBuildOptions defaults;
  mbao::KdBuildOptions everywhere, full_sweep;
  everywhere.min_triangles_to_clip = 0;
  full_sweep.prune_sweep = false;
  return {{"clip at >= " + std::to_string(defaults.min_triangles_to_clip) + " triangles (default)", defaults},
          {"clip everywhere", everywhere},
          {"default, every plane priced", full_sweep}};
}

// A copy of the scene whose tree is built with `options`.
std::shared_ptr<mbao::Scene> rebuilt(const BenchScene& s, const mbao::KdBuildOptions& options) {
  auto scene = std::make_shared<mbao::Scene>(s.scene->mesh(), s.name, s.scene->camera(), std::vector<std::string>{},
                                             s.scene->masks());
  scene->set_kd_build_options(options);
  return scene;
}

}  // namespace

json kd_builds(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options) {
  std::cout << "| scene | triangles | tree | build ms | nodes | leaf references | SAH cost | per ray (b=2): nodes"
               " | leaves | triangle tests |\n|---|---:|---|---:|---:|---:|---:|---:|---:|---:|\n";
  const std::vector<Variant> tried = variants();
  json rows = json::array();
  for (const BenchScene& s : scenes) {
    std::vector<std::vector<double>> build_ms(tried.size());
    for (int frame = 0; frame < options.frames; ++frame)
      for (std::size_t v = 0; v < tried.size(); ++v)
        build_ms[v].push_back(mbao::build_kd_tree(s.scene->mesh(), tried[v].options).stats.build_ms);
    json row = {{"scene", s.name}, {"triangles", s.scene->mesh().triangles.size()}, {"trees", json::array()}};
    for (std::size_t v = 0; v < tried.size(); ++v) {
      mbao::RenderSettings settings = options.settings;
      settings.bounces = 2;
      settings.traversal_stats = true;
      // The tree the rays walk, in the device's frame (see Scene::render_origin).
      const std::shared_ptr<mbao::Scene> scene = rebuilt(s, tried[v].options);
      const json counts = per_ray_counts(renderer.render(scene, s.camera, settings).stats);
      const mbao::KdTreeStats tree = scene->kd_tree()->stats;
      const double ms = median(build_ms[v]);
      std::cout << "| " << s.name << " | " << s.scene->mesh().triangles.size() << " | " << tried[v].name << " | "
                << fixed(ms, 1) << " | " << tree.nodes << " | " << tree.leaf_references << " | "
                << fixed(tree.sah_cost, 2) << " | " << fixed(counts["nodes_per_ray"], 2) << " | "
                << fixed(counts["leaves_per_ray"], 2) << " | " << fixed(counts["triangles_per_ray"], 2) << " |"
                << std::endl;
      row["trees"].push_back({{"tree", tried[v].name},
                              {"min_triangles_to_clip", tried[v].options.min_triangles_to_clip},
                              {"prune_sweep", tried[v].options.prune_sweep},
                              {"build_ms", ms},
                              {"build_ms_all", build_ms[v]},
                              {"stats", tree_stats_json(tree)},
                              {"per_ray", counts}});
    }
    // Builds next to each other share the machine's state: compare them pairwise.
    row["default_build_time_over"] = json::object();
    for (std::size_t v = 1; v < tried.size(); ++v) {
      std::vector<double> ratios;
      for (int frame = 0; frame < options.frames; ++frame) ratios.push_back(build_ms[0][frame] / build_ms[v][frame]);
      row["default_build_time_over"][tried[v].name] = median(ratios);
      std::cout << "| " << s.name << " | | default / " << tried[v].name << ", build time | " << fixed(median(ratios), 2)
                << " | | | | | | |" << std::endl;
    }
    rows.push_back(row);
  }
  std::cout << "\nBuild ms: median of " << options.frames
            << " builds of each tree, interleaved, on every hardware thread (the ratio: median over the pairs);"
               " per-ray counts: Table 1 configuration, b = 2, max_distance = inf.\n\n";
  return rows;
}

}  // namespace bench
