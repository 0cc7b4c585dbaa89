// The benchmark's parts. Each section measures one thing, prints a markdown
// table and returns its figures as JSON for bench/results/.
#pragma once

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "scene/scene.h"

namespace bench {

using nlohmann::json;

struct Options {
  std::string scenes_dir;
  std::string json_path;
  std::string device;
  int frames = 5;
  mbao::RenderSettings settings;               // the Table 1 configuration, with --width/--height/--samples/--traversal
  std::vector<std::string> sections;           // --sections; empty: all of them
  std::vector<std::size_t> work_groups = {0};  // --work-groups, for the organisation section; 0: the default
  std::vector<std::size_t> scale_sizes = {1000000, 4000000, 8400000, 16000000, 32000000};  // --scale-sizes: triangles
  std::string self;  // this executable, for the measurements that need a fresh process
  std::string command_line;
};

struct BenchScene {
  std::string name;
  std::shared_ptr<mbao::Scene> scene;
  mbao::Camera camera;
  std::filesystem::path file;  // empty for the built-in Cornell box
  double load_ms = 0.0;
};

// The seed paper's Table 1: every scene, b = 1 and 2, max_distance inf and the scene's own.
json table1(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options);
// Restart, push-down, short-stack and full-stack traversal, and lanes on CPUs, on every scene: frame time and
// per-ray counts.
json traversals(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options);
// The Cornell box with its kernels built without and with the alpha-mask path.
json mask_overhead(mbao::Renderer& renderer, const Options& options);
// Kernel build time in a fresh process: with empty caches, then with warm ones.
json kernel_builds(const Options& options);
// mbao beside Embree 3 on the same workload (only in builds with Embree).
json embree_comparison(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options);
// Load time and peak memory of each glTF scene: mbao's loader against loading everything.
json loading(const std::vector<BenchScene>& scenes, const Options& options);
// The kd-tree clipped everywhere against the default: build time, tree and per-ray counts.
json kd_builds(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options);
// Where each frame's time goes on every scene, at b = 1, 2 and HBAO: each kernel's and the read-backs' device
// time, from a queue of the section's own that records when its commands ran, beside the frame's.
json profile(const mbao::DeviceInfo& device, const std::vector<BenchScene>& scenes, const Options& options);
// Megakernel against wavefront on the Table 1 workload, interleaved, at each of --work-groups.
json organisation(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options);

// Bakes beside renders: the rays/s of a vertex bake and of a texture bake into generated UVs against
// the Table 1 render's, at b = 2, and the texture bake's time by stage.
json bakes(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options);

// What the child processes run (mbao_bench --child-load / --child-build-kernels).
int child_load(const std::string& path, bool everything);
int child_build_kernels(const std::string& device);
int child_scale(std::size_t triangles, const mbao::DeviceInfo& device, int width, int height);

// Growth with the scene: build, frame and peak memory of generated scenes of
// options.scale_sizes triangles, each in a fresh process, beside Embree's build.
json scale(const Options& options);

// Shared helpers.
double median(std::vector<double> values);
std::string fixed(double value, int digits);
// The max_distance values each scene is measured at: inf, then its camera's radius if it suggests one.
std::vector<float> distance_limits(const BenchScene& scene);
// HBAO's frame beside a Table 1 row's: its default directions and steps, the row's
// radius where finite, else the scene's (SPEC 1).
mbao::RenderSettings hbao_settings(const mbao::RenderSettings& row, float radius);
// A distance limit in the JSON ("inf" or the number) and in the tables ("inf" or one decimal).
json distance_json(float max_distance);
std::string distance_text(float max_distance);
// A kd-tree's size, shape and SAH cost.
json tree_stats_json(const mbao::KdTreeStats& tree);
// Nodes, leaves, triangle tests and restarts per ray of a render with traversal_stats.
json per_ray_counts(const mbao::RenderStats& counted);
// Median frame over `frames` renders, after one untimed render that builds the
// kernels and uploads the scene.
json measure_frames(mbao::Renderer& renderer, const BenchScene& scene, const mbao::RenderSettings& settings,
                    int frames);
// The process's peak resident set size so far (getrusage's ru_maxrss), in KiB.
long peak_rss_kb();
// Runs `command` in a shell and parses the last line it prints as JSON.
json run_child(const std::string& command);
std::string shell_quoted(const std::string& text);

}  // namespace bench
