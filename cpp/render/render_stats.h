#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "accel/kd_tree.h"

namespace mbao {

// What the traversals of a frame cost, summed over its rays (counting builds only).
struct TraversalTotals {
  std::uint64_t nodes = 0, leaves = 0, triangles = 0, restarts = 0;
};

struct RenderStats {
  double build_ms = 0.0;             // kd-tree build (done once per scene; see tree_reused)
  bool tree_reused = false;          // the tree existed before this render
  double kernel_build_ms = 0.0;      // getting the program (and, on first launch, its kernels) ready
  std::string kernel_cache;          // where the program came from: "memory", "disk" or "compiled"
  std::string kernel_options;        // what it was built for (SPEC features compiled in or out)
  std::string traversal_mode;        // the kd traversal the kernels ran ("auto" resolved for the device)
  std::string organisation;          // the ray-traced method's kernel organisation ("auto" resolved); empty for HBAO
  std::vector<std::string> plan;     // why "auto" chose as it did, a line per choice (RenderPlan::reasons)
  std::vector<std::string> kernels;  // render.cl's entry points the frame launched, in their order
  float max_distance = 0.0f;         // the AO radius the render used (SPEC 1)
  // Where it came from: "settings", "camera" (its suggestion), "scene" (HBAO's quarter diagonal) or
  // "none" (inf, for want of any).
  std::string max_distance_source;
  double upload_ms = 0.0;    // scene upload in this render; 0 when the scene was on the device
  double frame_ms = 0.0;     // camera rays, AO, the spatial filter and read-back of the image
  double gbuffer_ms = 0.0;   // HBAO's and G-buffer frames: the part of frame_ms that made the G-buffer
  double denoise_ms = 0.0;   // the spatial filter, where it ran (SPEC 7.3)
  double temporal_ms = 0.0;  // temporal accumulation, where it ran (SPEC 7.4)
  std::uint64_t rays_primary = 0;
  std::uint64_t rays_secondary = 0;
  std::size_t memory_bytes = 0;  // device memory: scene, tile buffers and image
  std::size_t tiles = 0;
  std::string device;
  KdTreeStats tree;
  std::optional<TraversalTotals> traversal;  // with RenderSettings::traversal_stats
};

struct RenderResult {
  int width = 0, height = 0;
  std::vector<float> ao;  // row-major, row 0 at the top; 1 = open
  // Per pixel, 255 x the fraction of camera samples that hit geometry, rounded up: 0 only where all missed.
  std::vector<std::uint8_t> coverage;
  // Bakes only: per pixel, the mean of its estimates' squares (SPEC 6.4).
  std::vector<float> ao_second_moment;
  // With RenderSettings::variance: per pixel, its variance (SPEC 7.1).
  std::vector<float> variance;
  // Renderer::gbuffer only: GBUFFER_PLANES planes of a float per pixel (kernels/mbao/gbuffer.h).
  std::vector<float> gbuffer;
  // A frame that accumulates (SPEC 7.4): per pixel, its history length n.
  std::vector<std::uint32_t> history_length;
  RenderStats stats;
};

}  // namespace mbao
