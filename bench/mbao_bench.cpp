// mbao's benchmark. By default:
// * the seed paper's Table 1 workload on the built-in Cornell box and on every
//   scene under --scenes (512x512, r = 4, branching, b = 1 and 2, rho = 1,
//   spp = 1), with max_distance = inf and again with the radius a scene's
//   camera.json suggests;
// * where each frame's time goes: each kernel's and the read-backs' device time
//   beside the frame's;
// * the kd traversals' frame times and per-ray counts, at b = 2;
// * mbao beside Embree 3 on the same workload (builds with Embree);
// * the Cornell box with kernels built without and with the alpha-mask path;
// * kernel build time in a fresh process, cold and warm;
// * load time and peak memory of each scene against loading everything;
// * the Table 1 workload with the megakernel and the wavefront, interleaved, at
//   each work-group size of --work-groups (default: the default size);
// * the kd-tree clipped everywhere against the default (build time, tree,
//   per-ray counts);
// * bakes beside renders: rays/s per vertex and per texel (generated UVs,
//   2048x2048), and the texture bake's stages.
// Prints markdown tables and writes everything as JSON. --sections picks some
// of table1, profile, traversals, embree, masks, kernel-builds, loading,
// organisation, kd-build, bake, scale (default: all).
//
//   mbao_bench [--scenes DIR] [--json FILE] [--device INDEX|NAME] [--frames N]
//              [--width W] [--height H] [--samples R] [--traversal auto|pushdown|restart|short-stack|stack|lanes]
//              [--sections A,B,...] [--work-groups N,M,...] [--origin-paths on|off] [--scale-sizes N,M,...]
//
// --origin-paths overrides the renderer's choice (RenderSettings::origin_paths);
// --scale-sizes gives the scale section's triangle counts.
#include <algorithm>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

#include "bench.h"
#include "core/timer.h"
#include "opencl/devices.h"
#include "scene/cornell_box.h"
#include "scene/gltf_loader.h"

namespace fs = std::filesystem;
using bench::json;

namespace {

[[noreturn]] void usage(const std::string& problem) {
  std::cerr << "mbao_bench: " << problem
            << "\nusage: mbao_bench [--scenes DIR] [--json FILE] [--device INDEX|NAME] [--frames N]"
               " [--width W] [--height H] [--samples R] [--traversal auto|pushdown|restart|short-stack|stack|lanes]"
               " [--sections A,B,...] [--work-groups N,M,...] [--origin-paths on|off] [--scale-sizes N,M,...]\n";
  std::exit(2);
}

const std::vector<std::string> kSections = {"table1",  "profile",      "traversals", "embree", "masks", "kernel-builds",
                                            "loading", "organisation", "kd-build",   "bake",   "scale"};

std::vector<std::string> split_commas(const std::string& list) {
  std::vector<std::string> items;
  std::istringstream in(list);
  for (std::string item; std::getline(in, item, ',');) items.push_back(item);
  return items;
}

std::vector<std::string> parse_sections(const std::string& list) {
  const std::vector<std::string> sections = split_commas(list);
  for (const std::string& section : sections)
    if (std::find(kSections.begin(), kSections.end(), section) == kSections.end()) usage("unknown section " + section);
  return sections;
}

std::vector<std::size_t> parse_sizes(const std::string& flag, const std::string& list) {
  std::vector<std::size_t> sizes;
  for (const std::string& size : split_commas(list)) sizes.push_back(std::size_t(std::stoul(size)));
  if (sizes.empty()) usage(flag + " needs at least one size");
  return sizes;
}

bool parse_on_off(const std::string& flag, const std::string& value) {
  if (value != "on" && value != "off") usage(flag + " takes on or off, not " + value);
  return value == "on";
}

bench::Options parse(int argc, char** argv) {
  bench::Options options;
  options.self = fs::canonical("/proc/self/exe").string();
  options.settings.samples = 4;
  options.settings.estimator = mbao::Estimator::Branching;
  // Sections run at max_distance = inf unless they set a scene's radius, not at the camera's suggestion.
  options.settings.max_distance = std::numeric_limits<float>::infinity();
  for (int i = 0; i < argc; ++i) options.command_line += (i ? " " : "") + std::string(argv[i]);
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) usage(flag + " needs a value");
    const std::string value = argv[++i];
    try {
      if (flag == "--scenes")
        options.scenes_dir = value;
      else if (flag == "--json")
        options.json_path = value;
      else if (flag == "--device")
        options.device = value;
      else if (flag == "--frames")
        options.frames = std::stoi(value);
      else if (flag == "--width")
        options.settings.width = std::stoi(value);
      else if (flag == "--height")
        options.settings.height = std::stoi(value);
      else if (flag == "--samples")
        options.settings.samples = std::stoi(value);
      else if (flag == "--traversal")
        options.settings.traversal = mbao::parse_traversal(value);
      else if (flag == "--sections")
        options.sections = parse_sections(value);
      else if (flag == "--work-groups")
        options.work_groups = parse_sizes(flag, value);
      else if (flag == "--scale-sizes")
        options.scale_sizes = parse_sizes(flag, value);
      else if (flag == "--origin-paths")
        options.settings.origin_paths = parse_on_off(flag, value);
      else
        usage("unknown option " + flag);
    } catch (const std::logic_error&) {
      usage("bad value for " + flag + ": " + value);
    }
  }
  if (options.frames < 1) usage("--frames must be >= 1");
  return options;
}

mbao::DeviceInfo pick_device(const std::string& spec) {
  if (spec.empty()) return mbao::default_device();
  if (spec.find_first_not_of("0123456789") == std::string::npos)
    return mbao::find_device(std::size_t(std::stoul(spec)));
  return mbao::find_device(spec);
}

std::vector<bench::BenchScene> load_scenes(const std::string& dir) {
  std::vector<bench::BenchScene> scenes;
  auto cornell = mbao::cornell_box();
  scenes.push_back({"cornell_box (built-in)", cornell, *cornell->camera(), {}, 0.0});
  if (dir.empty()) return scenes;
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(dir))
    if (fs::exists(entry.path() / "scene.glb") && fs::exists(entry.path() / "camera.json"))
      folders.push_back(entry.path());
  std::sort(folders.begin(), folders.end());
  for (const fs::path& folder : folders) {
    mbao::Stopwatch clock;
    auto scene = mbao::load_gltf((folder / "scene.glb").string());
    const double load_ms = clock.elapsed_ms();
    scenes.push_back({folder.filename().string(), scene, mbao::Camera::load((folder / "camera.json").string()),
                      folder / "scene.glb", load_ms});
  }
  return scenes;
}

std::string iso_date() {
  const std::time_t now = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return text;
}

bool wanted(const bench::Options& options, const std::string& section) {
  return options.sections.empty() ||
         std::find(options.sections.begin(), options.sections.end(), section) != options.sections.end();
}

int run(bench::Options options) {
  const mbao::DeviceInfo device = pick_device(options.device);
  mbao::Renderer& renderer = mbao::Renderer::for_device(device);
  const std::vector<bench::BenchScene> scenes = load_scenes(options.scenes_dir);
  std::cout << "Device: " << device.description() << " (" << device.version << ")\n\n";
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
                   {"frames", options.frames},
                   {"sections", options.sections.empty() ? kSections : options.sections},
                   {"work_groups", options.work_groups}}}};
  if (wanted(options, "table1")) report["results"] = bench::table1(renderer, scenes, options);
  if (wanted(options, "profile")) report["profile"] = bench::profile(device, scenes, options);
  if (wanted(options, "traversals")) report["traversals"] = bench::traversals(renderer, scenes, options);
#ifdef MBAO_BENCH_EMBREE
  if (wanted(options, "embree")) report["embree"] = bench::embree_comparison(renderer, scenes, options);
#else
  if (wanted(options, "embree"))
    std::cout << "(Built without Embree: no side-by-side comparison. Debian: libembree-dev.)\n\n";
#endif
  if (wanted(options, "masks")) report["mask_overhead"] = bench::mask_overhead(renderer, options);
  if (wanted(options, "kernel-builds")) report["kernel_builds"] = bench::kernel_builds(options);
  if (wanted(options, "loading")) report["loading"] = bench::loading(scenes, options);
  if (wanted(options, "organisation")) report["organisation"] = bench::organisation(renderer, scenes, options);
  if (wanted(options, "kd-build")) report["kd_build"] = bench::kd_builds(renderer, scenes, options);
  if (wanted(options, "bake")) report["bake"] = bench::bakes(renderer, scenes, options);
  if (wanted(options, "scale")) report["scale"] = bench::scale(options);
  if (!options.json_path.empty()) {
    const fs::path path(options.json_path);
    if (path.has_parent_path()) fs::create_directories(path.parent_path());
    std::ofstream(path) << report.dump(2) << "\n";
    std::cout << "Wrote " << options.json_path << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    // The measurements that need a process of their own run this executable again.
    if (argc >= 3 && std::string(argv[1]) == "--child-load")
      return bench::child_load(argv[2], argc >= 4 && std::string(argv[3]) == "--everything");
    if (argc >= 3 && std::string(argv[1]) == "--child-build-kernels") return bench::child_build_kernels(argv[2]);
    if (argc >= 6 && std::string(argv[1]) == "--child-scale")
      return bench::child_scale(std::stoul(argv[2]), pick_device(argv[3] == std::string("-") ? "" : argv[3]),
                                std::stoi(argv[4]), std::stoi(argv[5]));
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::cerr << "mbao_bench: " << e.what() << "\n";
    return 1;
  }
}
