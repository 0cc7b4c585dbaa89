// Rays, watertight ray/triangle intersection and the surface record a hit turns into.
#ifndef MBAO_GEOMETRY_H
#define MBAO_GEOMETRY_H

#define MBAO_NO_TRIANGLE 0xFFFFFFFFu

// The watertight test relies on a*b - c*d being rounded once per product: a
// fused multiply-add would make the edge functions of a shared edge, or of a
// triangle with coinciding corners, differ from exact zero in their sign.
#pragma OPENCL FP_CONTRACT OFF

// Bound on the rounding error of n float operations, relative to the result:
// gamma(n) = n u / (1 - n u) with u = 2^-24 (Higham; pbrt's notation).
#define MBAO_UNIT_ROUNDOFF (0.5f * FLT_EPSILON)
static inline float error_gamma(int n) {
  return (n * MBAO_UNIT_ROUNDOFF) / (1.0f - n * MBAO_UNIT_ROUNDOFF);
}

static inline float component(float3 v, int axis) {
  return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}

typedef struct Hit {
  float t;
  uint triangle;
  float b1, b2;  // barycentric weights of the triangle's second and third vertex
} Hit;

static inline Hit no_hit(void) {
  Hit hit;
  hit.t = INFINITY;
  hit.triangle = MBAO_NO_TRIANGLE;
  hit.b1 = 0.0f;
  hit.b2 = 0.0f;
  return hit;
}

// Per-ray setup of the watertight test (Woop, Benthin and Wald, JCGT 2013): the
// ray is turned into +z of a sheared frame where the triangle test is 2D.
typedef struct WatertightRay {
  float4 origin;
  uint4 axes;  // (kx, ky, kz, 3): one shuffle turns a vector into the ray's frame
  float shear_x, shear_y, shear_z;
} WatertightRay;

static inline WatertightRay make_watertight_ray(float3 origin, float3 dir) {
  WatertightRay ray;
  const float3 a = fabs(dir);
  const uint kz = (a.x > a.y) ? ((a.x > a.z) ? 0 : 2) : ((a.y > a.z) ? 1 : 2);
  uint kx = kz == 2 ? 0 : kz + 1;
  uint ky = kx == 2 ? 0 : kx + 1;
  const float dz = component(dir, (int)kz);
  if (dz < 0.0f) {  // keep the winding, so edge functions keep their signs
    const uint k = kx;
    kx = ky;
    ky = k;
  }
  ray.origin = (float4)(origin, 0.0f);
  ray.axes = (uint4)(kx, ky, kz, 3);
  ray.shear_x = component(dir, (int)kx) / dz;
  ray.shear_y = component(dir, (int)ky) / dz;
  ray.shear_z = 1.0f / dz;
  return ray;
}

// Edge functions exactly zero are recomputed in double, as the paper suggests,
// so a ray through a shared edge hits one of its two triangles and never neither.
static inline float edge_function(float ax, float ay, float bx, float by) {
  float e = ax * by - ay * bx;
#ifdef cl_khr_fp64
  if (e == 0.0f) e = (float)((double)ax * (double)by - (double)ay * (double)bx);
#endif
  return e;
}

// Intersects the ray with triangle (p0, p1, p2) for 0 < t <= t_max. On a hit
// returns 1 and writes t and the barycentrics of p1 and p2. Every hit with a
// positive t counts, however close: rays leaving a surface start far enough
// off it (surface.h) that they need no minimum distance, and so a surface
// just in front of a ray's origin is never skipped.
static inline int intersect_triangle(const WatertightRay* ray, float4 p0, float4 p1, float4 p2,
                                     float t_max, float* t_out, float* b1_out, float* b2_out) {
  // The corners relative to the origin, in the ray's frame (x, y across, z along).
  const float4 a = shuffle(p0 - ray->origin, ray->axes);
  const float4 b = shuffle(p1 - ray->origin, ray->axes);
  const float4 c = shuffle(p2 - ray->origin, ray->axes);
  const float az = a.z, bz = b.z, cz = c.z;
  const float ax = a.x - ray->shear_x * az;
  const float ay = a.y - ray->shear_y * az;
  const float bx = b.x - ray->shear_x * bz;
  const float by = b.y - ray->shear_y * bz;
  const float cx = c.x - ray->shear_x * cz;
  const float cy = c.y - ray->shear_y * cz;

  const float e0 = edge_function(bx, by, cx, cy);  // weight of p0
  const float e1 = edge_function(cx, cy, ax, ay);  // weight of p1
  const float e2 = edge_function(ax, ay, bx, by);  // weight of p2
  if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) return 0;
  const float det = e0 + e1 + e2;
  if (det == 0.0f) return 0;

  const float sz = ray->shear_z;
  const float t_scaled = e0 * (sz * az) + e1 * (sz * bz) + e2 * (sz * cz);
  if (det < 0.0f && (t_scaled >= 0.0f || t_scaled < t_max * det)) return 0;
  if (det > 0.0f && (t_scaled <= 0.0f || t_scaled > t_max * det)) return 0;

  const float inv_det = 1.0f / det;
  const float t = t_scaled * inv_det;
  if (!(t <= t_max)) return 0;

  *t_out = t;
  *b1_out = e1 * inv_det;
  *b2_out = e2 * inv_det;
  return 1;
}

// Clips the ray to an axis-aligned box and to [0, t_max]. The far distance is
// widened by the slab test's rounding error so a ray never slips past the box.
static inline int clip_to_box(float3 origin, float3 dir, float3 inv_dir, float3 lo, float3 hi,
                              float t_max, float* t_enter, float* t_exit) {
  float t0 = 0.0f, t1 = t_max;
  for (int axis = 0; axis < 3; ++axis) {
    const float o = component(origin, axis);
    if (component(dir, axis) == 0.0f) {
      if (o < component(lo, axis) || o > component(hi, axis)) return 0;
      continue;
    }
    const float inv = component(inv_dir, axis);
    float near = (component(lo, axis) - o) * inv;
    float far = (component(hi, axis) - o) * inv;
    if (near > far) {
      const float swap = near;
      near = far;
      far = swap;
    }
    far *= 1.0f + 2.0f * error_gamma(3);
    t0 = fmax(t0, near);
    t1 = fmin(t1, far);
  }
  *t_enter = t0;
  *t_exit = t1;
  return t0 <= t1;
}

#endif
