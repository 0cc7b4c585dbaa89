// The parameter groups that one host object supplies in order: each a list,
// X(type, name) with the OpenCL C type, that the kernels declare as
// parameters and the host's struct holds as fields (of type cl_<type>) and
// appends (render/ao_kernel_args.h), so that the two sides cannot disagree on
// an argument's place or type.
#ifndef MBAO_PARAM_GROUPS_H
#define MBAO_PARAM_GROUPS_H

// The camera (CameraArgs): trace_camera_rays, trace_camera_packets and temporal_accumulate.
#define MBAO_CAMERA_PARAM_LIST(X)                                          \
  X(float4, eye)                                                           \
  X(float4, forward)                                                       \
  X(float4, right)                                                         \
  X(float4, up)                                                            \
  X(float2, film_scale) /* tan of half the field of view, across and up */ \
  X(uint, width)                                                           \
  X(uint, height)

// The settings of every AO kernel of render.cl (AoArgs).
#define MBAO_AO_PARAM_LIST(X)                                                                     \
  X(float4, eye)       /* eye.w = 1: primary surfaces given (a bake's points), not camera hits */ \
  X(uint2, image_size) /* (width, height) */                                                      \
  X(uint, spp)                                                                                    \
  X(uint, bounces)                                                                                \
  X(uint, samples) /* r: directions per hit */                                                    \
  X(float, rho)                                                                                   \
  X(float, max_distance) /* inf: unlimited */                                                     \
  X(uint2, seed)                                                                                  \
  X(uint, direction_moments) /* 1: keep the moments of the directions at each camera hit (SPEC 7.1) */

#ifdef __OPENCL_VERSION__
// A list as parameters, each followed by a comma: a kernel writes
// `MBAO_AO_PARAMS uint first_position, ...`, with no comma of its own after it.
#define MBAO_PARAM_DECLARATION(type, name) type name,
#define MBAO_CAMERA_PARAMS MBAO_CAMERA_PARAM_LIST(MBAO_PARAM_DECLARATION)
#define MBAO_AO_PARAMS MBAO_AO_PARAM_LIST(MBAO_PARAM_DECLARATION)
#else
// A struct's fields, and its append_to(KernelArgs& args)'s body.
#define MBAO_PARAM_FIELD(type, name) cl_##type name;
#define MBAO_APPEND_PARAM(type, name) args.append(name);
#endif

#endif
