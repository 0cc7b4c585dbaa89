#include <algorithm>
#include <iostream>
#include <map>

#include "bake/bake_estimates.h"
#include "bake/dilation.h"
#include "bake/lightmap_uvs.h"
#include "bake/texel_layout.h"
#include "bake/vertex_points.h"
#include "bench.h"
#include "core/timer.h"
#include "scene/gltf_loader.h"

namespace bench {
namespace {

// Estimates per vertex: at least 16, and enough for 2^20 in all, so that small
// meshes measure tracing rather than the launches around it.
std::int64_t vertex_samples(const mbao::Scene& scene) {
  const auto vertices = std::int64_t(scene.mesh().positions.size());
  return std::clamp<std::int64_t>(((std::int64_t(1) << 20) + vertices - 1) / vertices, 16, 4096);
}
constexpr std::int64_t kTexelSamples = 2;  // the fewest that give a standard error
constexpr int kTextureSide = 2048;
constexpr int kPadding = 4;
// Smaller textures at which generated UVs' coverage is reported too: there
// padding takes more of the texture.
constexpr int kSmallerSides[] = {512, 1024};

// The scene again with its UV sets' materials, which a texture bake groups triangles by.
std::shared_ptr<mbao::Scene> with_materials(const BenchScene& s) {
  if (s.file.empty()) return s.scene;
  mbao::LoadOptions options;
  options.texcoords = true;
  return mbao::load_gltf(s.file.string(), options);
}

std::map<int, std::vector<std::uint32_t>> triangles_by_material(const mbao::Scene& scene) {
  std::map<int, std::vector<std::uint32_t>> groups;
  const std::vector<std::int32_t>& materials = scene.uv_sets().triangle_materials;
  for (std::uint32_t t = 0; t < scene.mesh().triangles.size(); ++t)
    groups[materials.empty() ? -1 : materials[t]].push_back(t);
  return groups;
}

json rays_json(double frame_ms, std::uint64_t rays) {
  return {{"frame_ms", frame_ms}, {"rays", rays}, {"mrays_per_s", double(rays) / frame_ms / 1e3}};
}

double covered_fraction(const mbao::TexelLayout& layout) {
  return double(layout.covered_count()) / (double(layout.width()) * layout.height());
}

// Generated UVs of every material in side x side texels, without a bake: the
// mean over materials of the fraction of texels covered, the charts and the time.
json uv_coverage(const mbao::Scene& scene, int side) {
  double covered = 0.0, uv_ms = 0.0;
  std::size_t charts = 0, materials = 0;
  for (const auto& [material, triangles] : triangles_by_material(scene)) {
    mbao::Stopwatch clock;
    const mbao::LightmapUvs uvs = mbao::generate_lightmap_uvs(scene.mesh(), triangles, side, side, kPadding);
    uv_ms += clock.elapsed_ms();
    covered += covered_fraction(*uvs.layout);
    charts += uvs.charts;
    ++materials;
  }
  return {{"side", side}, {"texels_covered", covered / double(materials)}, {"charts", charts}, {"uv_ms", uv_ms}};
}

// A per-vertex bake: the second of two, the first having built the kernels.
json vertex_bake(mbao::Renderer& renderer, const std::shared_ptr<mbao::Scene>& scene,
                 const mbao::RenderSettings& settings) {
  const mbao::VertexPoints points(scene->mesh(), scene->mesh().all_triangles());
  const std::int64_t samples = vertex_samples(*scene);
  mbao::bake_estimates(renderer, scene, settings, samples, points, 1024);
  const mbao::BakeEstimates bake = mbao::bake_estimates(renderer, scene, settings, samples, points, 1024);
  json result = rays_json(bake.stats.frame_ms, bake.stats.rays_secondary);
  result["samples"] = samples;
  return result;
}

// A texture bake of every material into generated UVs, each stage timed.
json texture_bake(mbao::Renderer& renderer, const std::shared_ptr<mbao::Scene>& scene,
                  const mbao::RenderSettings& settings) {
  double uv_ms = 0.0, trace_ms = 0.0, dilation_ms = 0.0, covered = 0.0;
  std::uint64_t rays = 0;
  std::size_t charts = 0, materials = 0;
  for (const auto& [material, triangles] : triangles_by_material(*scene)) {
    mbao::Stopwatch clock;
    const mbao::LightmapUvs uvs =
        mbao::generate_lightmap_uvs(scene->mesh(), triangles, kTextureSide, kTextureSide, kPadding);
    uv_ms += clock.elapsed_ms();  // the layout, made to check the charts, included
    const mbao::TexelLayout& layout = *uvs.layout;
    if (materials++ == 0) mbao::bake_estimates(renderer, scene, settings, kTexelSamples, layout, kTextureSide);
    mbao::BakeEstimates bake = mbao::bake_estimates(renderer, scene, settings, kTexelSamples, layout, kTextureSide);
    trace_ms += bake.stats.frame_ms;
    rays += bake.stats.rays_secondary;
    clock = mbao::Stopwatch();
    mbao::dilate(layout.covered(), kTextureSide, kTextureSide, kPadding, {&bake.values, &bake.standard_error});
    dilation_ms += clock.elapsed_ms();
    charts += uvs.charts;
    covered += covered_fraction(layout);
  }
  json result = rays_json(trace_ms, rays);
  result["side"] = kTextureSide;
  result["materials"] = materials;
  result["charts"] = charts;
  result["texels_covered"] = covered / double(materials);  // the mean over materials of their textures' fraction
  result["uv_ms"] = uv_ms;
  result["dilation_ms"] = dilation_ms;
  result["total_ms"] = uv_ms + trace_ms + dilation_ms;
  return result;
}

}  // namespace

// A row per scene and estimator: the render and the bakes trace with the same
// estimator and r, so that their rays are alike but for where they start. The
// texture bake with the bake's default estimator only: Sponza's takes minutes.
json bakes(mbao::Renderer& renderer, const std::vector<BenchScene>& scenes, const Options& options) {
  std::cout << "| scene | max_distance | estimator | render Mrays/s | render AO Mrays/s | vertex bake Mrays/s | "
               "texture bake Mrays/s | render AO / vertex | render AO / texture | texture bake s (UVs and layout, "
               "tracing, dilation) | texels covered | device |\n"
            << "|---|---:|---|---:|---:|---:|---:|---:|---:|---|---:|---|\n";
  json rows = json::array();
  for (const BenchScene& s : scenes) {
    const std::shared_ptr<mbao::Scene> scene = with_materials(s);
    for (const mbao::Estimator estimator : {mbao::Estimator::Path, mbao::Estimator::Branching}) {
      mbao::RenderSettings settings = options.settings;
      settings.bounces = 2;
      settings.estimator = estimator;
      settings.max_distance = distance_limits(s).back();  // the scene's own radius where it suggests one
      json render = measure_frames(renderer, s, settings, options.frames);
      // A bake traces no camera rays, and many of a render's miss the scene's
      // box at once: its AO rays over the whole frame compare with a bake's.
      const double render_rate = double(render["rays_secondary"]) / double(render["frame_ms"]) / 1e3;
      render["ao_mrays_per_s"] = render_rate;
      const json vertex = vertex_bake(renderer, scene, settings);
      json row = {{"scene", s.name},
                  {"max_distance", distance_json(*settings.max_distance)},
                  {"estimator", mbao::to_string(estimator)},
                  {"render", render},
                  {"vertex_bake", vertex}};
      std::cout << "| " << s.name << " | " << distance_text(*settings.max_distance) << " | "
                << mbao::to_string(estimator) << " | " << fixed(render["mrays_per_s"], 1) << " | "
                << fixed(render_rate, 1) << " | " << fixed(vertex["mrays_per_s"], 1) << " | ";
      if (estimator == mbao::Estimator::Path) {
        const json texture = texture_bake(renderer, scene, settings);
        row["texture_bake"] = texture;
        for (const int side : kSmallerSides) row["uv_coverage"].push_back(uv_coverage(*scene, side));
        std::cout << fixed(texture["mrays_per_s"], 1) << " | " << fixed(render_rate / double(vertex["mrays_per_s"]), 2)
                  << " | " << fixed(render_rate / double(texture["mrays_per_s"]), 2) << " | "
                  << fixed(double(texture["total_ms"]) / 1e3, 1) << " (" << fixed(double(texture["uv_ms"]) / 1e3, 1)
                  << ", " << fixed(double(texture["frame_ms"]) / 1e3, 1) << ", "
                  << fixed(double(texture["dilation_ms"]) / 1e3, 1) << ") | " << fixed(texture["texels_covered"], 2);
      } else {
        std::cout << " | " << fixed(render_rate / double(vertex["mrays_per_s"]), 2) << " | | | ";
      }
      std::cout << " | " << renderer.device().name << " |" << std::endl;
      rows.push_back(row);
    }
  }
  std::cout << "\nb = 2, rho = 1, r = " << options.settings.samples
            << ", the render and the bakes with one estimator. Render: " << options.settings.width << "x"
            << options.settings.height << "; its Mrays/s with the camera rays, its AO Mrays/s without them (but "
            << "over the whole frame). Vertex bake: 16 estimates per vertex, more for "
            << "small meshes (2^20 in all). Texture bake: every material into generated UVs at " << kTextureSide << "x"
            << kTextureSide << ", padding " << kPadding << ", " << kTexelSamples
            << " estimates per texel; its Mrays/s over the tracing alone; texels covered: the mean over "
            << "materials of the fraction of their texture's texels a triangle covers (in the JSON also at "
            << "smaller sides, UVs alone).\n\n";
  return rows;
}

}  // namespace bench
