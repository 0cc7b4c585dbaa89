#include "render/ao_kernel_args.h"

namespace mbao {

cl_float4 to_float4(const glm::vec3& v) { return {{v.x, v.y, v.z, 0.0f}}; }

cl_uint2 seed_words(std::uint64_t seed) { return {{cl_uint(seed & 0xFFFFFFFFu), cl_uint(seed >> 32)}}; }

CameraArgs::CameraArgs(const Camera& camera, const RenderSettings& s) {
  const CameraBasis basis(camera);
  const float aspect = float(s.width) / float(s.height);
  eye = to_float4(camera.eye);
  forward = to_float4(basis.forward);
  right = to_float4(basis.right);
  up = to_float4(basis.up);
  film_scale = cl_float2{{basis.tan_half_vfov * aspect, basis.tan_half_vfov}};
  width = cl_uint(s.width);
  height = cl_uint(s.height);
}

void CameraArgs::append_to(KernelArgs& args) const {MBAO_CAMERA_PARAM_LIST(MBAO_APPEND_PARAM)}

AoArgs::AoArgs(const Camera& camera, const RenderSettings& s, PrimarySurfaces primaries)
    : eye(to_float4(camera.eye)),
      image_size{{cl_uint(s.width), cl_uint(s.height)}},
      spp(cl_uint(s.spp)),
      bounces(cl_uint(s.bounces)),
      samples(cl_uint(s.samples)),
      rho(s.rho),
      max_distance(s.radius()),
      seed(seed_words(s.seed)),
      direction_moments(s.direction_moments()) {
  eye.s[3] = primaries == PrimarySurfaces::GivenPoints ? 1.0f : 0.0f;
}

void AoArgs::append_to(KernelArgs& args) const { MBAO_AO_PARAM_LIST(MBAO_APPEND_PARAM) }

}  // namespace mbao
