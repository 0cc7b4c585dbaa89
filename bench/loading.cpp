// Loading only what AO uses, against loading everything: time and peak memory
// of each glTF scene, each load in a process of its own.
#include <iostream>

#include "bench.h"
#include "core/timer.h"
#include "scene/gltf_accessor_reader.h"
#include "scene/gltf_loader.h"

namespace bench {
namespace {

// What a loader that takes everything does: tinygltf with its own image
// loader (every image decoded to 8-bit RGBA, kept in the model) and every
// attribute of every primitive read into arrays that it keeps.
struct EverythingLoaded {
  tinygltf::Model model;
  std::vector<std::vector<float>> attributes;
  std::vector<std::vector<std::uint32_t>> indices;
};

EverythingLoaded load_everything(const std::string& path) {
  EverythingLoaded loaded;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  if (!loader.LoadBinaryFromFile(&loaded.model, &error, &warning, path) &&
      !loader.LoadASCIIFromFile(&loaded.model, &error, &warning, path))
    throw std::runtime_error(path + ": " + error);
  const mbao::AccessorReader reader(loaded.model, path);
  for (const tinygltf::Mesh& mesh : loaded.model.meshes)
    for (const tinygltf::Primitive& primitive : mesh.primitives) {
      for (const auto& [name, accessor] : primitive.attributes)
        loaded.attributes.push_back(
            name.rfind("TEXCOORD_", 0) == 0
                ? reader.texcoords(accessor, name)
                : reader.floats(accessor, loaded.model.accessors[std::size_t(accessor)].type, name));
      if (primitive.indices >= 0) loaded.indices.push_back(reader.indices(primitive.indices, "indices"));
    }
  return loaded;
}

}  // namespace

int child_load(const std::string& path, bool everything) {
  mbao::Stopwatch clock;
  if (everything) {
    const EverythingLoaded loaded = load_everything(path);
  } else {
    const auto scene = mbao::load_gltf(path);
  }
  std::cout << json{{"load_ms", clock.elapsed_ms()}, {"peak_rss_kb", peak_rss_kb()}}.dump() << "\n";
  return 0;
}

json loading(const std::vector<BenchScene>& scenes, const Options& options) {
  std::cout << "| scene | mbao load ms | peak MiB | load-everything ms | peak MiB |\n|---|---:|---:|---:|---:|\n";
  json rows = json::array();
  for (const BenchScene& s : scenes) {
    if (s.file.empty()) continue;
    const std::string command = shell_quoted(options.self) + " --child-load " + shell_quoted(s.file.string());
    const json mbao_load = run_child(command);
    const json everything = run_child(command + " --everything");
    std::cout << "| " << s.name << " | " << fixed(mbao_load["load_ms"], 1) << " | "
              << fixed(mbao_load["peak_rss_kb"].get<double>() / 1024.0, 1) << " | " << fixed(everything["load_ms"], 1)
              << " | " << fixed(everything["peak_rss_kb"].get<double>() / 1024.0, 1) << " |\n";
    rows.push_back({{"scene", s.name}, {"mbao", mbao_load}, {"everything", everything}});
  }
  std::cout << "\nEach load in a fresh process; peak = its maximum resident set size.\n\n";
  return rows;
}

}  // namespace bench
