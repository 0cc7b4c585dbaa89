#pragma once

// Which kernel variant runs, and why: the one place where "auto" is decided.
//
// A plan turns what a render asks for (its settings), where it runs (the
// device's class) and what it runs on (the scene's tree depth, alpha masks and
// normals) into the kernels' variant: how one ray walks the kd-tree, whether a
// bounce's rays are walked sixteen to a work item (lanes), how the AO work is
// cut into kernels, and which features each program is compiled with.
// docs/kernel-variants.md has the device table with the measurement behind
// each entry.

#include <cstdint>
#include <string>
#include <vector>

#include "opencl/devices.h"
#include "render/render_settings.h"
#include "scene/scene.h"

namespace mbao {

// What one class of device runs where the settings leave the choice to mbao.
// Each field's default is "no": a profile names what it turns on.
struct DeviceProfile {
  const char* device_class = "";           // "CPU", "GPU" or "other" (accelerators: unmeasured)
  Traversal walk = Traversal::ShortStack;  // for rays walked one per work item
  int min_lanes_depth = 0;                 // lanes for trees at least this deep (0: never)
  KernelOrganisation organisation = KernelOrganisation::Megakernel;  // where the wavefront can run the settings
  bool load_both_children = false;  // in the full stack's walk (MBAO_LOAD_BOTH_CHILDREN)
  int min_origin_path_depth = 0;    // origin paths for trees at least this deep (0: never)
  // The device reads host memory: it reads the scene's tree where it is
  // (CL_MEM_USE_HOST_PTR, render/device_scene.h).
  bool shares_host_memory = false;
  // Where it does, scenes of at least this many triangles are read from the
  // mesh's own vertices and indices (MBAO_INDEXED_TRIANGLES), not from 48
  // bytes of coordinates per triangle in a buffer of their own (0: never).
  std::size_t min_indexed_triangles = 0;
  // HBAO's G-buffer walks its camera rays in packets (lanes), whatever the tree's depth.
  bool gbuffer_packets = false;
  // render.cl's registers per work item, where the compiler takes a cap (cl_nv_compiler_options;
  // 0: the compiler's choice). Fewer registers, more rays in flight to hide the walks' memory latency.
  int max_registers = 0;
};

// The row of the device table for `device`.
const DeviceProfile& device_profile(const DeviceInfo& device);

// What a plan needs to know of a scene.
struct SceneTraits {
  int tree_depth = 0;
  std::size_t triangles = 0;
  bool alpha_masks = false;
  bool vertex_normals = false;
  static SceneTraits of(const Scene& scene);  // builds the scene's tree if it has none
};

enum class Program { Render, Trace, Hbao, Denoise, Temporal };

// One build of one program: its file and the defines that program reads.
struct ProgramVariant {
  Program program = Program::Render;
  Traversal walk = Traversal::Stack;  // MBAO_TRAVERSAL: never Auto; the screen-space passes (hbao.cl,
                                      // denoise.cl, temporal.cl) walk no tree and read no define
  bool count_traversal = false;       // render.cl, trace.cl
  bool alpha_masks = false;
  bool load_both_children = false;  // full-stack walks only (Stack, Lanes)
  bool origin_paths = false;        // render.cl, walks of one ray only
  bool indexed_triangles = false;   // render.cl, trace.cl
  int max_registers = 0;            // render.cl: -cl-nv-maxrregcount, a build option, not a define (0: none)

  const char* file() const;
  // "-DMBAO_TRAVERSAL=3 -DMBAO_COUNT_TRAVERSAL=0 ...": the defines `program` reads, in a fixed order,
  // then the register cap's build option where there is one.
  std::string options() const;
};

// Every variant a plan can ask for: the programs a build of mbao may compile.
std::vector<ProgramVariant> all_program_variants();

// What a render is asked for: the image its settings' method makes, or its
// G-buffer alone (Renderer::gbuffer).
enum class RenderProduct { Image, GBuffer };

// What a frame's tiles make: the AO from their camera hits, with the G-buffer
// planes that the screen-space passes after it read (where
// RenderSettings::filtered); the planes HBAO reads, alone; or the whole G-buffer.
enum class FrameOutput { AmbientOcclusion, HbaoGBuffer, GBuffer };

// How a frame's AO runs after its camera rays: not at all (their G-buffer
// alone), in the megakernel, or in the wavefront, each bounce over a queue or
// as a stream of rays walked sixteen to a work item.
enum class AoLaunches { None, Megakernel, Wavefront, StreamedWavefront };

// The entry points of render.cl that a frame launches, by their part in it;
// empty where the frame has no such part.
struct FrameKernels {
  AoLaunches ao = AoLaunches::None;
  std::string camera_rays;                  // trace_camera_rays, or trace_camera_packets: every frame
  std::size_t camera_samples_per_item = 1;  // MBAO_LANES for trace_camera_packets
  std::string megakernel;                   // ao_branching or ao_path: the megakernel organisation
  // The wavefront: its first bounce and the bounces after, each over a queue,
  // then the pixels' values from the counts.
  std::string first_bounce, bounce, finish;
  // The wavefront with lanes: each bounce as its rays, their walk sixteen to a
  // work item, and their outcomes (render/streamed_bounces.h), then `finish`.
  std::string stream_rays, stream_trace, stream_hits;

  std::vector<std::string> in_launch_order() const;  // the names, the empty ones left out
  bool wavefront() const { return ao == AoLaunches::Wavefront || ao == AoLaunches::StreamedWavefront; }
};

struct RenderPlan {
  Traversal traversal;              // never Auto; for HBAO the G-buffer's walk
  KernelOrganisation organisation;  // never Auto for the ray-traced method; Megakernel for camera rays alone
  ProgramVariant program;           // render.cl; for HBAO its G-buffer's, and hbao.cl follows
  FrameOutput output = FrameOutput::AmbientOcclusion;
  std::uint32_t gbuffer_planes = 0;  // what the camera rays write of the G-buffer (kernels/mbao/gbuffer.h's masks)
  FrameKernels kernels;
  // Pixels per tile, each tile its own launches: what one launch's hit records
  // and rays are bounded by and, in the wavefront, its queues; the settings'
  // tile_pixels where that is less.
  std::size_t tile_pixels = 0;
  // The scene goes to the device with its vertex normals, which the kernels
  // then shade with: the render asks for shading normals and the scene has them.
  bool shading_normals = false;
  std::vector<std::string> reasons;  // one line per choice made for "auto"
};

// Whether `device` reads a scene of `triangles` triangles from the mesh's own
// vertices (ProgramVariant::indexed_triangles): what every plan for it says.
bool plans_indexed_triangles(const DeviceInfo& device, std::size_t triangles);

// Throws nothing: `settings` is validated before (RenderSettings::validate).
RenderPlan plan_render(const RenderSettings& settings, const DeviceInfo& device, const SceneTraits& scene,
                       RenderProduct product = RenderProduct::Image);

// A ray query (Renderer::trace): trace.cl with the walk `requested` resolves to.
ProgramVariant plan_trace(Traversal requested, bool count_traversal, const DeviceInfo& device,
                          const SceneTraits& scene);

}  // namespace mbao
