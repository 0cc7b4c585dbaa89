// The seed paper's Table 1 workload on the built-in Cornell box and on every
// scene under --scenes: 512x512, r = 4, branching, b = 1 and 2, rho = 1,
// spp = 1; with max_distance = inf and again with the radius a scene's
// camera.json suggests. Prints a markdown table and writes JSON.
//
//   mbao_bench [--scenes DIR] [--json FILE] [--device INDEX|NAME] [--frames N]
//              [--width W] [--height H] [--samples R] [--traversal pushdown|restart]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "opencl/devices.h"
#include "render/renderer.h"
#include "scene/cornell_box.h"
#include "scene/gltf_loader.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct Options {
  std::string scenes_dir;
  std::string json_path;
  std::string device;
  int frames = 5;
  mbao::RenderSettings settings;
  std::string command_line;
};

struct BenchScene {
  std::string name;
  std::shared_ptr<mbao::Scene> scene;
  mbao::Camera camera;
  double load_ms;
};

[[noreturn]] void usage(const std::string& problem) {
  std::cerr << "mbao_bench: " << problem
            << "\nusage: mbao_bench [--scenes DIR] [--json FILE] [--device INDEX|NAME] [--frames N]"
               " [--width W] [--height H] [--samples R] [--traversal pushdown|restart]\n";
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options options;
  options.settings.samples = 4;
  options.settings.estimator = mbao::Estimator::Branching;
  for (int i = 0; i < argc; ++i) options.command_line += (i ? " " : "") + std::string(argv[i]);
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) usage(flag + " needs a value");
    const std::string value = argv[++i];
    try {
      if (flag == "--scenes") options.scenes_dir = value;
      else if (flag == "--json") options.json_path = value;
      else if (flag == "--device") options.device = value;
      else if (flag == "--frames") options.frames = std::stoi(value);
      else if (flag == "--width") options.settings.width = std::stoi(value);
      else if (flag == "--height") options.settings.height = std::stoi(value);
      else if (flag == "--samples") options.settings.samples = std::stoi(value);
      else if (flag == "--traversal") options.settings.traversal = mbao::parse_traversal(value);
      else usage("unknown option " + flag);
    } catch (const std::logic_error& e) {
      usage("bad value for " + flag + ": " + value);
    }
  }
  if (options.frames < 1) usage("--frames must be >= 1");
  return options;
}

mbao::DeviceInfo pick_device(const std::string& spec) {
  if (spec.empty()) return mbao::default_device();
  if (spec.find_first_not_of("0123456789") == std::string::npos) return mbao::find_device(std::size_t(std::stoul(spec)));
  return mbao::find_device(spec);
}

std::vector<BenchScene> load_scenes(const std::string& dir) {
  std::vector<BenchScene> scenes;
  auto cornell = mbao::cornell_box();
  scenes.push_back({"cornell_box (built-in)", cornell, *cornell->camera(), 0.0});
  if (dir.empty()) return scenes;
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(dir))
    if (fs::exists(entry.path() / "scene.glb") && fs::exists(entry.path() / "camera.json")) folders.push_back(entry.path());
  std::sort(folders.begin(), folders.end());
  for (const fs::path& folder : folders) {
    const auto start = std::chrono::steady_clock::now();
    auto scene = mbao::load_gltf((folder / "scene.glb").string());
    const double load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    scenes.push_back({folder.filename().string(), scene, mbao::Camera::load((folder / "camera.json").string()), load_ms});
  }
  return scenes;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// Median frame over `frames` renders, after one untimed render that builds the
// kernels and uploads the scene.
json measure(mbao::Renderer& renderer, const BenchScene& s, mbao::RenderSettings settings, int frames) {
  renderer.render(s.scene, s.camera, settings);
  std::vector<double> times;
  mbao::RenderStats stats;
  for (int f = 0; f < frames; ++f) {
    const mbao::RenderResult result = renderer.render(s.scene, s.camera, settings);
    times.push_back(result.stats.frame_ms);
    stats = result.stats;
  }
  const double frame_ms = median(times);
  const double rays = double(stats.rays_primary + stats.rays_secondary);
  return {{"bounces", settings.bounces},
          {"frame_ms", frame_ms},
          {"frame_ms_all", times},
          {"rays_primary", stats.rays_primary},
          {"rays_secondary", stats.rays_secondary},
          {"mrays_per_s", rays / frame_ms / 1e3},
          {"memory_bytes", stats.memory_bytes}};
}

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

std::string iso_date() {
  const std::time_t now = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  try {
    const mbao::DeviceInfo device = pick_device(options.device);
    mbao::Renderer& renderer = mbao::Renderer::for_device(device);
    const std::vector<BenchScene> scenes = load_scenes(options.scenes_dir);

    json report = {{"device", device.description()},
                   {"device_version", device.version},
                   {"date", iso_date()},
                   {"command", options.command_line},
                   {"config",
                    {{"width", options.settings.width},
                     {"height", options.settings.height},
                     {"samples", options.settings.samples},
                     {"estimator", "branching"},
                     {"rho", 1.0},
                     {"spp", 1},
                     {"traversal", mbao::to_string(options.settings.traversal)},
                     {"frames", options.frames}}},
                   {"results", json::array()}};

    std::cout << "| scene | triangles | max_distance | build ms | b=1 ms | b=2 ms | b=1 Mrays/s | b=2 Mrays/s | device |\n"
              << "|---|---:|---:|---:|---:|---:|---:|---:|---|\n";
    for (const BenchScene& s : scenes) {
      std::vector<float> radii = {std::numeric_limits<float>::infinity()};
      if (s.camera.max_distance) radii.push_back(*s.camera.max_distance);
      const mbao::KdTreeStats tree = s.scene->kd_tree()->stats;
      for (float radius : radii) {
        mbao::RenderSettings settings = options.settings;
        settings.max_distance = radius;
        json row = {{"scene", s.name},
                    {"triangles", s.scene->mesh().triangles.size()},
                    {"max_distance", std::isinf(radius) ? json("inf") : json(radius)},
                    {"load_ms", s.load_ms},
                    {"build_ms", tree.build_ms},
                    {"tree",
                     {{"nodes", tree.nodes},
                      {"leaves", tree.leaves},
                      {"empty_leaves", tree.empty_leaves},
                      {"max_depth", tree.max_depth},
                      {"mean_triangles_per_leaf", tree.mean_triangles_per_leaf},
                      {"sah_cost", tree.sah_cost},
                      {"memory_bytes", tree.memory_bytes}}},
                    {"frames", json::array()}};
        for (int bounces : {1, 2}) {
          settings.bounces = bounces;
          row["frames"].push_back(measure(renderer, s, settings, options.frames));
        }
        const json& b1 = row["frames"][0];
        const json& b2 = row["frames"][1];
        std::cout << "| " << s.name << " | " << s.scene->mesh().triangles.size() << " | "
                  << (std::isinf(radius) ? std::string("inf") : fixed(radius, 1)) << " | " << fixed(tree.build_ms, 1)
                  << " | " << fixed(b1["frame_ms"], 1) << " | " << fixed(b2["frame_ms"], 1) << " | "
                  << fixed(b1["mrays_per_s"], 1) << " | " << fixed(b2["mrays_per_s"], 1) << " | " << device.name
                  << " |" << std::endl;
        report["results"].push_back(row);
      }
    }
    std::cout << "\nDevice: " << device.description() << " (" << device.version << "). " << options.settings.width << "x"
              << options.settings.height << ", r=" << options.settings.samples
              << ", branching, rho=1, spp=1; frame = median of " << options.frames
              << " (camera rays + AO + read-back); Mrays/s counts primary and secondary rays.\n";
    if (!options.json_path.empty()) {
      fs::path path(options.json_path);
      if (path.has_parent_path()) fs::create_directories(path.parent_path());
      std::ofstream(path) << report.dump(2) << "\n";
      std::cout << "Wrote " << options.json_path << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "mbao_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
