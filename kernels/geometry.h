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
static inline float error_gamma(int n) { return (n * MBAO_UNIT_ROUNDOFF) / (1.0f - n * MBAO_UNIT_ROUNDOFF); }

static inline float component(float3 v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

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

// A hit as the kernels store it in their buffers: (t, triangle, b1, b2) as bits.
static inline uint4 bits_of_hit(Hit hit) {
  return (uint4)(as_uint(hit.t), hit.triangle, as_uint(hit.b1), as_uint(hit.b2));
}

static inline Hit hit_of_bits(uint4 bits) {
  Hit hit;
  hit.t = as_float(bits.x);
  hit.triangle = bits.y;
  hit.b1 = as_float(bits.z);
  hit.b2 = as_float(bits.w);
  return hit;
}

// Per-ray setup of the watertight test (Woop, Benthin and Wald, JCGT 2013): the
// ray is turned into +z of a sheared frame where the triangle test is 2D.
typedef struct WatertightRay {
  uint kx, ky, kz;                     // the axes that become x, y and z of the ray's frame
  float origin_x, origin_y, origin_z;  // the origin's coordinates along kx, ky and kz
  float shear_x, shear_y, shear_z;
  float edge_error;  // see edge_errors
} WatertightRay;

// A triangle as the test reads it: per axis, the coordinates of its corners
// (p0, p1, p2, 0) in one vector. The ray's frame is then three loads by the
// ray's axes and the test runs on the three corners at once; with a vector per
// corner it would take a permutation by the ray's axes per corner, which the
// compiler made a store and three loads.
typedef struct TriangleCoordinates {
  float4 along[3];
} TriangleCoordinates;

// Where the tests read a triangle: the scene's array of TriangleCoordinates in
// global memory, or, with MBAO_INDEXED_TRIANGLES (scene.h), a copy made from
// the mesh's own vertices and indices, in private memory.
#ifndef MBAO_INDEXED_TRIANGLES
#define MBAO_INDEXED_TRIANGLES 0
#endif
#if MBAO_INDEXED_TRIANGLES
#define MBAO_TRIANGLE_SPACE
// The coordinates along `axis`, picked by selects: an index into a private
// array made PoCL keep it in memory, and the tests ran scalar.
static inline float4 triangle_along(const TriangleCoordinates* t, uint axis) {
  return axis == 0 ? t->along[0] : (axis == 1 ? t->along[1] : t->along[2]);
}
#else
#define MBAO_TRIANGLE_SPACE __global
static inline float4 triangle_along(__global const TriangleCoordinates* t, uint axis) { return t->along[axis]; }
#endif

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
  ray.kx = kx;
  ray.ky = ky;
  ray.kz = kz;
  ray.origin_x = component(origin, (int)kx);
  ray.origin_y = component(origin, (int)ky);
  ray.origin_z = component(origin, (int)kz);
  ray.shear_x = component(dir, (int)kx) / dz;
  ray.shear_y = component(dir, (int)ky) / dz;
  ray.shear_z = 1.0f / dz;
  ray.edge_error = error_gamma(10) * farthest_in_box(origin, lo, hi);
  return ray;
}

// A triangle's corners relative to the ray's origin, in the ray's frame: lane
// k of each vector is corner p_k.
typedef struct FrameTriangle {
  float4 x, y;  // across the ray (sheared)
  float4 z;     // along it
} FrameTriangle;

static inline FrameTriangle triangle_in_ray_frame(const WatertightRay* ray,
                                                  MBAO_TRIANGLE_SPACE const TriangleCoordinates* t) {
  FrameTriangle f;
  f.z = triangle_along(t, ray->kz) - ray->origin_z;
  f.x = (triangle_along(t, ray->kx) - ray->origin_x) - ray->shear_x * f.z;
  f.y = (triangle_along(t, ray->ky) - ray->origin_y) - ray->shear_y * f.z;
  return f;
}

// Whether any lane is set, as ors of the lanes: PoCL's any() tests them one
// after another, with branches.
static inline int any_lane(int3 v) { return (v.x | v.y | v.z) != 0; }

// Bounds on the rounding errors of the edge functions (e0, e1, e2). In float
// an edge function is within 5 u R (|x_p| + |y_p| + |x_q| + |y_q|) of its
// exact value for the ray's shear, to first order, for its corners p and q in
// the ray's frame (u = 2^-24; R, the farthest_in_box of the ray, bounds
// |x| + |y| + |z| of the corners relative to the origin before the shear, and
// so the error of their x and y, 3 u R); nearer zero than twice that its sign
// is unknown.
static inline float3 edge_errors(const WatertightRay* ray, const FrameTriangle* f) {
  const float3 across = (fabs(f->x) + fabs(f->y)).xyz;
  return ray->edge_error * (across.yzx + across.zxy);
}

#if MBAO_USE_FP64
// The edge function of corners p and q from their coordinates along (kx, ky,
// kz), in double: the differences from the origin are exact and the shear and
// products keep 29 more bits than in float.
static inline float edge_function_in_double(const WatertightRay* ray, float3 p, float3 q) {
  const double3 o = (double3)(ray->origin_x, ray->origin_y, ray->origin_z);
  const double3 a = convert_double3(p) - o, b = convert_double3(q) - o;
  const double ax = a.x - (double)ray->shear_x * a.z;
  const double ay = a.y - (double)ray->shear_y * a.z;
  const double bx = b.x - (double)ray->shear_x * b.z;
  const double by = b.y - (double)ray->shear_y * b.z;
  return (float)(ax * by - ay * bx);
}

// The edge functions whose sign float leaves unknown, recomputed in double from
// the corners themselves.
static inline float3 edge_functions_in_double(const WatertightRay* ray,
                                              MBAO_TRIANGLE_SPACE const TriangleCoordinates* t, float3 e,
                                              int3 unknown) {
  const float4 kx = triangle_along(t, ray->kx), ky = triangle_along(t, ray->ky), kz = triangle_along(t, ray->kz);
  const float3 p0 = (float3)(kx.x, ky.x, kz.x), p1 = (float3)(kx.y, ky.y, kz.y), p2 = (float3)(kx.z, ky.z, kz.z);
  if (unknown.x) e.x = edge_function_in_double(ray, p1, p2);
  if (unknown.y) e.y = edge_function_in_double(ray, p2, p0);
  if (unknown.z) e.z = edge_function_in_double(ray, p0, p1);
  return e;
}
#endif

// The edge functions (e0, e1, e2) of the edges (p1, p2), (p2, p0) and (p0, p1):
// the weights of p0, p1 and p2. Where float leaves a sign unknown (edge_errors)
// it is recomputed in double. Each depends on its edge alone, so the two
// triangles of a shared edge decide alike and a ray through it hits one of them
// (Woop et al.'s watertightness); and the edges of a T-junction, whose corners
// are collinear but not shared, agree to double precision, where float would
// leave a crack along the long edge.
static inline float3 edge_functions(const WatertightRay* ray, MBAO_TRIANGLE_SPACE const TriangleCoordinates* t,
                                    const FrameTriangle* f) {
  const float3 x = f->x.xyz, y = f->y.xyz;
  float3 e = x.yzx * y.zxy - y.yzx * x.zxy;
#if MBAO_USE_FP64
  const int3 unknown = fabs(e) <= edge_errors(ray, f);
  if (any_lane(unknown)) e = edge_functions_in_double(ray, t, e, unknown);
#endif
  return e;
}

// Intersects the ray with the triangle for 0 < t <= t_max. On a hit returns 1
// and writes t and the barycentrics of p1 and p2. Every hit with a positive t
// counts, however close: rays leaving a surface start far enough off it
// (surface.h) that they need no minimum distance, and so a surface just in
// front of a ray's origin is never skipped.
static inline int intersect_triangle(const WatertightRay* ray, MBAO_TRIANGLE_SPACE const TriangleCoordinates* triangle,
                                     float t_max, float* t_out, float* b1_out, float* b2_out) {
  const FrameTriangle f = triangle_in_ray_frame(ray, triangle);
  const float3 e = edge_functions(ray, triangle, &f);
  // The signs as ors of lanes, not with || and &&, which the compiler makes a
  // chain of branches on each edge's sign: a ray misses most triangles it is
  // tested against, on either side at random, and such branches go wrong often.
  if (any_lane(e < 0.0f) & any_lane(e > 0.0f)) return 0;
  const float det = e.x + e.y + e.z;
  if (det == 0.0f) return 0;

  // Barycentrics before distances: the edge functions grow as the square of
  // the corners' distances, and the weighted sum of distances as their cube,
  // which would overflow float beyond distances of about 10^12 and underflow
  // below 10^-13; this way only the edge functions limit the range.
  const float inv_det = 1.0f / det;
  const float3 b = e * inv_det;
  const float t = (b.x * f.z.x + b.y * f.z.y + b.z * f.z.z) * ray->shear_z;
  if (!(t > 0.0f && t <= t_max)) return 0;

  *t_out = t;
  *b1_out = b.y;
  *b2_out = b.z;
  return 1;
}

// Clips the ray to an axis-aligned box and to [0, t_max]. The far distance is
// widened by the slab test's rounding error so a ray never slips past the box.
// The three slabs are clipped at once: the loop over axes this replaces took
// every component through a chain of selects. A slab the ray does not move
// across (1 / dir infinite) bounds no distance; the ray misses the box unless
// its origin lies in that slab.
static inline int clip_to_box(float3 origin, float3 dir, float3 inv_dir, float3 lo, float3 hi, float t_max,
                              float* t_enter, float* t_exit) {
  const int3 parallel = dir == 0.0f;
  if (any_lane(parallel & ((origin < lo) | (origin > hi)))) return 0;
  const float3 to_lo = (lo - origin) * inv_dir, to_hi = (hi - origin) * inv_dir;
  const int3 heads_down = to_lo > to_hi;
  const float3 near = select(select(to_lo, to_hi, heads_down), (float3)(-INFINITY), parallel);
  const float3 far =
      select(select(to_hi, to_lo, heads_down) * (1.0f + 2.0f * error_gamma(3)), (float3)(INFINITY), parallel);
  const float t0 = fmax(fmax(0.0f, near.x), fmax(near.y, near.z));
  const float t1 = fmin(fmin(t_max, far.x), fmin(far.y, far.z));
  *t_enter = t0;
  *t_exit = t1;
  return t0 <= t1;
}

#endif
