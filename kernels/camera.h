// The pinhole camera of SPEC 3.1, shared by every kernel that shoots camera rays.
#ifndef MBAO_CAMERA_H
#define MBAO_CAMERA_H

// The direction through the point `in_pixel` ((0.5, 0.5): the centre) of pixel
// `pixel` (row by row from the top left); film_scale is tan(vfov/2) times
// (width/height, 1).
static inline float3 camera_ray_direction(float3 forward, float3 right, float3 up, float2 film_scale, uint width,
                                          uint height, uint pixel, float2 in_pixel) {
  const float u = (((float)(pixel % width) + in_pixel.x) / (float)width) * 2.0f - 1.0f;
  const float v = 1.0f - (((float)(pixel / width) + in_pixel.y) / (float)height) * 2.0f;
  return normalize(forward + u * film_scale.x * right + v * film_scale.y * up);
}

// Where the point `from_eye` (a point less the eye) lies in the image, as
// camera_ray_direction inverted: .xy in pixels, each pixel's centre at its
// column and row; .z the point's depth along `forward`, <= 0 where the point
// is not in front of the camera.
static inline float3 camera_image_position(float3 forward, float3 right, float3 up, float2 film_scale, uint width,
                                           uint height, float3 from_eye) {
  const float depth = dot(from_eye, forward);
  const float u = dot(from_eye, right) / (depth * film_scale.x), v = dot(from_eye, up) / (depth * film_scale.y);
  return (float3)((u + 1.0f) * 0.5f * (float)width - 0.5f, (1.0f - v) * 0.5f * (float)height - 0.5f, depth);
}

#endif
