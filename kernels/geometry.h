// Rays, watertight ray/triangle intersection and the surface record a hit turns into.
#ifndef MBAO_GEOMETRY_H
#define MBAO_GEOMETRY_H

#define MBAO_NO_TRIANGLE 0xFFFFFFFFu

// The double-precision fallbacks (near-zero edge functions, geometric normals)
// where the device has fp64, float where it has not. Building with
// -DMBAO_USE_FP64=0 takes the float paths on any device, so that they can be
// tested where fp64 exists (tests/test_without_fp64.py).
#ifndef MBAO_USE_FP64
#ifdef cl_khr_fp64
#define MBAO_USE_FP64 1
#else
#define MBAO_USE_FP64 0
#endif
#endif

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
  float edge_error;  // see edge_function
} WatertightRay;

// A corner relative to the ray's origin, in the ray's frame.
typedef struct FrameCorner {
  float x, y, z;  // x, y across the ray (sheared), z along it
  float across;   // |x| + |y|
} FrameCorner;

// The largest 1-norm |x| + |y| + |z| of a point of the box [lo, hi] relative to
// origin: it bounds that of every corner of the scene.
static inline float farthest_in_box(float3 origin, float3 lo, float3 hi) {
  const float3 far = fmax(fabs(lo - origin), fabs(hi - origin));
  return far.x + far.y + far.z;
}

// The ray (origin, dir) for the watertight test of triangles inside [lo, hi].
static inline WatertightRay make_watertight_ray(float3 origin, float3 dir, float3 lo, float3 hi) {
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
  ray.edge_error = error_gamma(10) * farthest_in_box(origin, lo, hi);
  return ray;
}

static inline FrameCorner corner_in_ray_frame(const WatertightRay* ray, float4 p) {
  const float4 a = shuffle(p - ray->origin, ray->axes);
  FrameCorner c;
  c.x = a.x - ray->shear_x * a.z;
  c.y = a.y - ray->shear_y * a.z;
  c.z = a.z;
  c.across = fabs(c.x) + fabs(c.y);
  return c;
}

#if MBAO_USE_FP64
static inline double double_component(double3 v, uint axis) {
  return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}

// The edge function of corners p and q from their coordinates, in double: the
// differences from the origin are exact and the shear and products keep 29
// more bits than in float.
static inline float edge_function_in_double(const WatertightRay* ray, float4 p, float4 q) {
  const double3 o = convert_double3(ray->origin.xyz);
  const double3 a = convert_double3(p.xyz) - o, b = convert_double3(q.xyz) - o;
  const uint kx = ray->axes.x, ky = ray->axes.y, kz = ray->axes.z;
  const double ax = double_component(a, kx) - (double)ray->shear_x * double_component(a, kz);
  const double ay = double_component(a, ky) - (double)ray->shear_y * double_component(a, kz);
  const double bx = double_component(b, kx) - (double)ray->shear_x * double_component(b, kz);
  const double by = double_component(b, ky) - (double)ray->shear_y * double_component(b, kz);
  return (float)(ax * by - ay * bx);
}
#endif

// The edge function of corners p and q (a and b in the ray's frame). In float
// it is within 5 u R (a.across + b.across) of its exact value for the ray's
// shear, to first order (u = 2^-24; R, the farthest_in_box of the ray, bounds
// |x| + |y| + |z| of p and q relative to the origin before the shear, and so
// the error of their x and y, 3 u R). Nearer zero than twice that its sign is
// unknown, and it is recomputed in double from the corners themselves. The
// test depends on the edge alone, so the two triangles of a shared edge decide
// alike and a ray through it hits one of them (Woop et al.'s watertightness);
// and the edges of a T-junction, whose corners are collinear but not shared,
// agree to double precision, where float would leave a crack along the long edge.
static inline float edge_function(const WatertightRay* ray, float4 p, float4 q, const FrameCorner* a,
                                  const FrameCorner* b) {
  float e = a->x * b->y - a->y * b->x;
#if MBAO_USE_FP64
  if (fabs(e) <= ray->edge_error * (a->across + b->across)) e = edge_function_in_double(ray, p, q);
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
  const FrameCorner a = corner_in_ray_frame(ray, p0);
  const FrameCorner b = corner_in_ray_frame(ray, p1);
  const FrameCorner c = corner_in_ray_frame(ray, p2);

  const float e0 = edge_function(ray, p1, p2, &b, &c);  // weight of p0
  const float e1 = edge_function(ray, p2, p0, &c, &a);  // weight of p1
  const float e2 = edge_function(ray, p0, p1, &a, &b);  // weight of p2
  if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) return 0;
  const float det = e0 + e1 + e2;
  if (det == 0.0f) return 0;

  // Barycentrics before distances: the edge functions grow as the square of
  // the corners' distances, and the weighted sum of distances as their cube,
  // which would overflow float beyond distances of about 10^12 and underflow
  // below 10^-13; this way only the edge functions limit the range.
  const float inv_det = 1.0f / det;
  const float b0 = e0 * inv_det, b1 = e1 * inv_det, b2 = e2 * inv_det;
  const float t = (b0 * a.z + b1 * b.z + b2 * c.z) * ray->shear_z;
  if (!(t > 0.0f && t <= t_max)) return 0;

  *t_out = t;
  *b1_out = b1;
  *b2_out = b2;
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
