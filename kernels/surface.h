// What a hit becomes: a point with its rounding-error bound and the two normals
// of SPEC 3.3, and the robust origin of a ray leaving it.
#ifndef MBAO_SURFACE_H
#define MBAO_SURFACE_H

#include "mbao/float_steps.h"
#include "scene.h"

// How far a ray leaving a surface starts off it, in float steps of the
// triangle's largest coordinate: far more than the rounding error with which a
// ray/triangle test can place the ray's origin on the wrong side of that
// triangle's plane, or of a coplanar neighbour's (the Cornell box light lies in
// the ceiling).
#define MBAO_ORIGIN_OFFSET_STEPS 256.0f

// The unit normal of triangle (p0, p1, p2). The cross product of a needle's or
// a sliver's two nearly parallel edges cancels: in float it keeps few correct
// bits (degrees off at an aspect ratio of 10^6) or none (a zero vector, a NaN
// normal, for a triangle whose area only exceeds zero in the last bits). In
// double the corners' differences are exact and the products keep 29 more bits.
static inline float3 geometric_normal(float3 p0, float3 p1, float3 p2) {
#if MBAO_USE_FP64
  const double3 q0 = convert_double3(p0);
  return convert_float3(normalize(cross(convert_double3(p1) - q0, convert_double3(p2) - q0)));
#else
  return normalize(cross(p1 - p0, p2 - p0));
#endif
}

// v times 2^-ilogb(x) where p = inverse_power_of_two(x): by p.high, then by
// p.low, the order in which the product is exact (mbao/float_steps.h).
static inline float3 scaled_by(float3 v, PowerOfTwo p) { return v * p.high * p.low; }

// Scales v by a power of two so that its largest component lies in [1, 2):
// direction kept exactly, and nothing a dot product or sum of such vectors
// computes overflows or underflows. Zero stays zero.
static inline float3 unit_scale(float3 v) {
  const float largest = fmax(fmax(fabs(v.x), fabs(v.y)), fabs(v.z));
  if (!(largest > 0.0f)) return v;
  return scaled_by(v, inverse_power_of_two(largest));
}

// The unit direction of the vertex normals n0, n1, n2 interpolated with weights
// b0, b1, b2, or zero where that is zero. Normals of any finite length count by
// their direction and relative length, however long or short: the three are
// scaled together before they are added (no overflow), and the sum before it is
// normalized (no underflow in its squared length).
static inline float3 interpolated_normal(float3 n0, float3 n1, float3 n2, float b0, float b1, float b2) {
  const float3 m = fmax(fmax(fabs(n0), fabs(n1)), fabs(n2));
  const float largest = fmax(fmax(m.x, m.y), m.z);
  if (largest == 0.0f) return m;
  const PowerOfTwo scale = inverse_power_of_two(largest);
  const float3 n = unit_scale(b0 * scaled_by(n0, scale) + b1 * scaled_by(n1, scale) + b2 * scaled_by(n2, scale));
  return any(n != 0.0f) ? normalize(n) : n;
}

typedef struct Surface {
  float3 position;
  float offset;             // distance along the normal at which rays leave it
  float3 geometric_normal;  // unit, on the side the incoming ray came from
  float3 shading_normal;    // unit, turned to the same side
} Surface;

static inline Surface make_surface(const SceneView* scene, Hit hit, float3 incoming) {
  const float3 p0 = triangle_corner(scene, hit.triangle, 0);
  const float3 p1 = triangle_corner(scene, hit.triangle, 1);
  const float3 p2 = triangle_corner(scene, hit.triangle, 2);
  const float b0 = 1.0f - hit.b1 - hit.b2;

  Surface s;
  // Interpolating the corners is more accurate than origin + t * dir.
  s.position = b0 * p0 + hit.b1 * p1 + hit.b2 * p2;
  const float3 magnitude = fmax(fmax(fabs(p0), fabs(p1)), fabs(p2));
  s.offset = MBAO_ORIGIN_OFFSET_STEPS * FLT_EPSILON * fmax(fmax(magnitude.x, magnitude.y), magnitude.z);

  float3 ng = geometric_normal(p0, p1, p2);
  if (dot(ng, incoming) > 0.0f) ng = -ng;
  s.geometric_normal = ng;

  s.shading_normal = ng;
  // The host uploads vertex normals only where the render shades with them.
  if (scene->vertex_normals) {
    const uint v = 3 * hit.triangle;
    const float3 ns =
        interpolated_normal(scene->vertex_normals[scene->triangle_vertices[v]].xyz,
                            scene->vertex_normals[scene->triangle_vertices[v + 1]].xyz,
                            scene->vertex_normals[scene->triangle_vertices[v + 2]].xyz, b0, hit.b1, hit.b2);
    // A zero interpolated normal means "no normal here": keep the geometric one.
    if (any(ns != 0.0f)) s.shading_normal = dot(ns, ng) < 0.0f ? -ns : ns;
  }
  return s;
}

// Where the rays leaving the surface start: moved off it along the geometric
// normal, the side they leave on (a direction below it is blocked, SPEC 3.3),
// then rounded away from the surface so that it moves even where the offset is
// below a float step. One point for all of them, so that their walks can share
// its path down the kd-tree (kd_traversal.h).
static inline float3 leaving_point(const Surface* s) {
  const float3 offset = s->offset * s->geometric_normal;
  float3 p = s->position + offset;
  p.x = float_step_toward(p.x, offset.x);
  p.y = float_step_toward(p.y, offset.y);
  p.z = float_step_toward(p.z, offset.z);
  return p;
}

#endif
