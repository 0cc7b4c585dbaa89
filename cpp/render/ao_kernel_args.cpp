#include "render/ao_kernel_args.h"

namespace mbao {

cl_float4 to_float4(const glm::vec3& v) { return {{v.x, v.y, v.z, 0.0f}}; }

cl_uint2 seed_words(std::uint64_t seed) { return {{cl_uint(seed & 0xFFFFFFFFu), cl_uint(seed >> 32)}}; }

cl_uint set_camera_args(cl::Kernel& kernel, cl_uint arg, const Camera& camera, const RenderSettings& s) {
  const CameraBasis basis(camera);
  const float aspect = float(s.width) / float(s.height);
  kernel.setArg(arg++, to_float4(camera.eye));
  kernel.setArg(arg++, to_float4(basis.forward));
  kernel.setArg(arg++, to_float4(basis.right));
  kernel.setArg(arg++, to_float4(basis.up));
  kernel.setArg(arg++, cl_float2{{basis.tan_half_vfov * aspect, basis.tan_half_vfov}});
  kernel.setArg(arg++, cl_uint(s.width));
  kernel.setArg(arg++, cl_uint(s.height));
  return arg;
}

cl_uint set_ao_args(cl::Kernel& kernel, cl_uint arg, const Camera& camera, const RenderSettings& s) {
  kernel.setArg(arg++, to_float4(camera.eye));
  kernel.setArg(arg++, cl_uint2{{cl_uint(s.width), cl_uint(s.height)}});
  kernel.setArg(arg++, cl_uint(s.spp));
  kernel.setArg(arg++, cl_uint(s.bounces));
  kernel.setArg(arg++, cl_uint(s.samples));
  kernel.setArg(arg++, s.rho);
  kernel.setArg(arg++, s.max_distance);
  kernel.setArg(arg++, seed_words(s.seed));
  return arg;
}

}  // namespace mbao
