#pragma once

#include <cstdint>

#include "opencl/opencl.h"
#include "render/render_settings.h"
#include "scene/camera.h"

namespace mbao {

// The buffers of one render that the AO kernels share, whichever way they are
// organised: the tile's camera hits in, the frame's image out.
struct FrameBuffers {
  cl::Buffer camera_hits;       // per camera sample of the tile
  cl::Buffer ao, coverage, secondary_rays;  // per pixel of the frame
  cl::Buffer traversal_totals;  // 4 x ulong, only when counting
};

cl_float4 to_float4(const glm::vec3& v);
cl_uint2 seed_words(std::uint64_t seed);

// Sets the camera parameters that trace_camera_rays and hbao_gbuffer share (eye,
// forward, right, up, film scale, width, height) from `arg` on; returns the next index.
cl_uint set_camera_args(cl::Kernel& kernel, cl_uint arg, const Camera& camera, const RenderSettings& s);

// Sets render.cl's MBAO_AO_PARAMS from argument `arg` on; returns the next argument's index.
cl_uint set_ao_args(cl::Kernel& kernel, cl_uint arg, const Camera& camera, const RenderSettings& s);

}  // namespace mbao
