// What a hit becomes: a point with its rounding-error bound and the two normals
// of SPEC 3.3, and the robust origin of a ray leaving it.
#ifndef MBAO_SURFACE_H
#define MBAO_SURFACE_H

#include "scene.h"

typedef struct Surface {
  float3 position;
  float3 position_error;    // bound on |computed - exact| per component
  float3 geometric_normal;  // unit, on the side the incoming ray came from
  float3 shading_normal;    // unit, turned to the same side
} Surface;

static inline Surface make_surface(const SceneView* scene, Hit hit, float3 incoming) {
  const float3 p0 = triangle_corner(scene, hit.triangle, 0);
  const float3 p1 = triangle_corner(scene, hit.triangle, 1);
  const float3 p2 = triangle_corner(scene, hit.triangle, 2);
  const float b0 = 1.0f - hit.b1 - hit.b2;

  Surface s;
  // Interpolating the corners is more accurate than origin + t * dir, and its
  // error is bounded by gamma(7) times the sum of the terms' magnitudes.
  s.position = b0 * p0 + hit.b1 * p1 + hit.b2 * p2;
  s.position_error = error_gamma(7) * (fabs(b0 * p0) + fabs(hit.b1 * p1) + fabs(hit.b2 * p2));

  float3 ng = normalize(cross(p1 - p0, p2 - p0));
  if (dot(ng, incoming) > 0.0f) ng = -ng;
  s.geometric_normal = ng;

  s.shading_normal = ng;
  if (scene->vertex_normals) {
    const uint v = 3 * hit.triangle;
    const float3 n = b0 * scene->vertex_normals[scene->triangle_vertices[v]].xyz +
                     hit.b1 * scene->vertex_normals[scene->triangle_vertices[v + 1]].xyz +
                     hit.b2 * scene->vertex_normals[scene->triangle_vertices[v + 2]].xyz;
    const float length_squared = dot(n, n);
    // A zero interpolated normal means "no normal here": keep the geometric one.
    if (length_squared > 0.0f && isfinite(length_squared)) {
      const float3 ns = n * rsqrt(length_squared);
      s.shading_normal = dot(ns, ng) < 0.0f ? -ns : ns;
    }
  }
  return s;
}

// The origin of a ray leaving the surface along dir (on the geometric normal's
// side): moved off the surface by the position's error bound projected on the
// normal, then rounded away, so the ray cannot re-hit the surface it leaves
// (pbrt-v4's offset, section 6.8.6).
static inline float3 offset_origin(const Surface* s, float3 dir) {
  const float3 n = s->geometric_normal;
  const float distance = dot(fabs(n), s->position_error);
  float3 offset = distance * n;
  if (dot(dir, n) < 0.0f) offset = -offset;
  float3 p = s->position + offset;
  p.x = offset.x > 0.0f ? nextafter(p.x, INFINITY) : (offset.x < 0.0f ? nextafter(p.x, -INFINITY) : p.x);
  p.y = offset.y > 0.0f ? nextafter(p.y, INFINITY) : (offset.y < 0.0f ? nextafter(p.y, -INFINITY) : p.y);
  p.z = offset.z > 0.0f ? nextafter(p.z, INFINITY) : (offset.z < 0.0f ? nextafter(p.z, -INFINITY) : p.z);
  return p;
}

#endif
