// The scene as the kernels see it: the kd-tree, the triangles it indexes and,
// only where the scene and the settings need them, vertex normals and alpha masks.
#ifndef MBAO_SCENE_H
#define MBAO_SCENE_H

#include "mbao/alpha_mask.h"
#include "mbao/kd_node.h"
#include "geometry.h"

// Compiled in only for scenes with MASK materials (SPEC 3.2).
#ifndef MBAO_ALPHA_MASKS
#define MBAO_ALPHA_MASKS 0
#endif

typedef struct SceneView {
  __global const KdNode* nodes;
  __global const uint* leaf_entries;              // the node array as words, each leaf's entries after it
  __global const TriangleCoordinates* triangles;  // relative to Scene::render_origin; NULL where indexed
  __global const float* vertex_positions;         // x, y, z per vertex, in world space (only where indexed)
  __global const uint* triangle_vertices;         // 3 vertex ids per triangle (where indexed or with normals)
  __global const float4* vertex_normals;          // NULL: geometric normals everywhere
  __global const uint* triangle_masks;            // per triangle: a masked_triangles index or MBAO_NOT_MASKED
  __global const MaskedTriangle* masked_triangles;
  __global const MaskTexture* mask_textures;
  __global const uchar* mask_texels;
  float3 bounds_lo, bounds_hi;
  float3 render_origin;  // Scene::render_origin, what the vertices are moved by
} SceneView;

// Every kernel that traces takes the scene as its first parameters, in this
// order; buffers a scene does not need are NULL.
#define MBAO_SCENE_PARAMS                                                                         \
  __global const KdNode *kd_nodes, __global const TriangleCoordinates *triangles,                 \
      __global const float *vertex_positions, __global const uint *triangle_vertices,             \
      __global const float4 *vertex_normals, __global const uint *triangle_masks,                 \
      __global const MaskedTriangle *masked_triangles, __global const MaskTexture *mask_textures, \
      __global const uchar *mask_texels, float4 bounds_lo, float4 bounds_hi, float4 render_origin

#define MBAO_SCENE_VIEW()                                                                                   \
  ((SceneView){kd_nodes, (__global const uint*)kd_nodes, triangles, vertex_positions, triangle_vertices,    \
               vertex_normals, triangle_masks, masked_triangles, mask_textures, mask_texels, bounds_lo.xyz, \
               bounds_hi.xyz, render_origin.xyz})

#if MBAO_INDEXED_TRIANGLES
// Triangle t's coordinates from the mesh's vertices, moved as the host moves
// them for the other layout: the same floats, so the same hits.
static inline TriangleCoordinates indexed_triangle(const SceneView* scene, uint t) {
  const uint3 v = vload3(t, scene->triangle_vertices);
  const float3 p0 = vload3(v.x, scene->vertex_positions) - scene->render_origin;
  const float3 p1 = vload3(v.y, scene->vertex_positions) - scene->render_origin;
  const float3 p2 = vload3(v.z, scene->vertex_positions) - scene->render_origin;
  TriangleCoordinates c;
  c.along[0] = (float4)(p0.x, p1.x, p2.x, 0.0f);
  c.along[1] = (float4)(p0.y, p1.y, p2.y, 0.0f);
  c.along[2] = (float4)(p0.z, p1.z, p2.z, 0.0f);
  return c;
}
// Declares `name`, where the tests read triangle t (MBAO_TRIANGLE_SPACE).
#define MBAO_TRIANGLE_AT(name, scene, t)                                  \
  const TriangleCoordinates name##_copy = indexed_triangle((scene), (t)); \
  const TriangleCoordinates* name = &name##_copy
#else
#define MBAO_TRIANGLE_AT(name, scene, t) __global const TriangleCoordinates* name = (scene)->triangles + (t)
#endif

static inline float3 triangle_corner(const SceneView* scene, uint triangle, int corner) {
  MBAO_TRIANGLE_AT(t, scene, triangle);
  MBAO_TRIANGLE_SPACE const float* along = (MBAO_TRIANGLE_SPACE const float*)t->along;
  return (float3)(along[corner], along[4 + corner], along[8 + corner]);
}

// Whether a hit at barycentrics (b1, b2) of `triangle` is solid: false where an
// alpha mask cuts the surface away (for every kind of ray).
static inline int hit_is_solid(const SceneView* scene, uint triangle, float b1, float b2) {
  if (!MBAO_ALPHA_MASKS) return 1;
  const uint slot = scene->triangle_masks[triangle];
  if (slot == MBAO_NOT_MASKED) return 1;
  const MaskedTriangle masked = scene->masked_triangles[slot];
  return mask_is_opaque(masked, scene->mask_textures[masked.texture], scene->mask_texels, b1, b2);
}

#endif
