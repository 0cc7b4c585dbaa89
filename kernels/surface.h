// What a hit becomes: a point with its rounding-error bound and the two normals
// of SPEC 3.3, and the robust origin of a ray leaving it.
#ifndef MBAO_SURFACE_H
#define MBAO_SURFACE_H

#include "scene.h"

// Compiled in only when the render uses shading normals and the scene has them.
#ifndef MBAO_SHADING_NORMALS
#define MBAO_SHADING_NORMALS 0
#endif

// How far a ray leaving a surface starts off it, in float steps of the
// triangle's largest coordinate: far more than the rounding error with which a
// ray/triangle test can place the ray's origin on the wrong side of that
// triangle's plane, or of a coplanar neighbour's (the Cornell box light lies in
// the ceiling).
#define MBAO_ORIGIN_OFFSET_STEPS 256.0f

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

  float3 ng = normalize(cross(p1 - p0, p2 - p0));
  if (dot(ng, incoming) > 0.0f) ng = -ng;
  s.geometric_normal = ng;

  s.shading_normal = ng;
#if MBAO_SHADING_NORMALS
  {
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
#endif
  return s;
}

// The origin of a ray leaving the surface along dir: moved off the surface
// along the geometric normal, to dir's side, then rounded away from the
// surface so that it moves even where the offset is below a float step.
static inline float3 offset_origin(const Surface* s, float3 dir) {
  const float3 n = s->geometric_normal;
  float3 offset = s->offset * n;
  if (dot(dir, n) < 0.0f) offset = -offset;
  float3 p = s->position + offset;
  p.x = offset.x > 0.0f ? nextafter(p.x, INFINITY) : (offset.x < 0.0f ? nextafter(p.x, -INFINITY) : p.x);
  p.y = offset.y > 0.0f ? nextafter(p.y, INFINITY) : (offset.y < 0.0f ? nextafter(p.y, -INFINITY) : p.y);
  p.z = offset.z > 0.0f ? nextafter(p.z, INFINITY) : (offset.z < 0.0f ? nextafter(p.z, -INFINITY) : p.z);
  return p;
}

#endif
