#pragma once

#include <cstdint>

#include "mbao/param_groups.h"
#include "opencl/kernel_args.h"
#include "opencl/opencl.h"
#include "render/render_settings.h"
#include "scene/camera.h"

namespace mbao {

// The buffers of one render that the AO kernels share, whichever way they are
// organised: the tile's camera hits in, the frame's image out.
struct FrameBuffers {
  cl::Buffer camera_hits;       // per camera sample of the tile: AO frames only
  cl::Buffer ao, coverage;      // per pixel of the frame: not in a G-buffer frame
  cl::Buffer secondary_rays;    // per pixel of the frame: AO frames only
  cl::Buffer ao_second_moment;  // per pixel, the mean of its samples' squares: bakes only (SPEC 6.4)
  cl::Buffer ao_variance;       // per pixel, its variance: when asked or filtered (SPEC 7.1)
  cl::Buffer gbuffer;           // the planes of the frame's set (kernels/mbao/gbuffer.h): when read (SPEC 7.2)
  cl::Buffer traversal_totals;  // 4 x ulong, only when counting
};

// What a frame's AO starts from: the hits of the camera rays it traces, or
// surface points a bake gives tile by tile, shaded on their front sides (SPEC 6.1).
enum class PrimarySurfaces { CameraHits, GivenPoints };

cl_float4 to_float4(const glm::vec3& v);
cl_uint2 seed_words(std::uint64_t seed);

// The kernels' MBAO_CAMERA_PARAMS (kernels/mbao/param_groups.h); HBAO's pass takes some of them.
struct CameraArgs {
  CameraArgs(const Camera& camera, const RenderSettings& s);
  void append_to(KernelArgs& args) const;

  MBAO_CAMERA_PARAM_LIST(MBAO_PARAM_FIELD)
};

// render.cl's MBAO_AO_PARAMS (kernels/mbao/param_groups.h).
struct AoArgs {
  AoArgs(const Camera& camera, const RenderSettings& s, PrimarySurfaces primaries = PrimarySurfaces::CameraHits);
  void append_to(KernelArgs& args) const;

  MBAO_AO_PARAM_LIST(MBAO_PARAM_FIELD)
};

}  // namespace mbao
