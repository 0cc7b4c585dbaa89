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
  __global const uint* leaf_entries;       // the node array as words, each leaf's entries after it
  __global const TriangleCoordinates* triangles;  // relative to Scene::render_origin
  __global const uint* triangle_vertices;  // 3 vertex ids per triangle (only with normals)
  __global const float4* vertex_normals;   // NULL: geometric normals everywhere
  __global const uint* triangle_masks;     // per triangle: a masked_triangles index or MBAO_NOT_MASKED
  __global const MaskedTriangle* masked_triangles;
  __global const MaskTexture* mask_textures;
  __global const uchar* mask_texels;
  float3 bounds_lo, bounds_hi;
} SceneView;

// Every kernel that traces takes the scene as its first parameters, in this
// order; buffers a scene does not need are NULL.
#define MBAO_SCENE_PARAMS                                                                       \
  __global const KdNode *kd_nodes, __global const TriangleCoordinates *triangles,               \
      __global const uint *triangle_vertices, __global const float4 *vertex_normals,            \
      __global const uint *triangle_masks, __global const MaskedTriangle *masked_triangles,     \
      __global const MaskTexture *mask_textures, __global const uchar *mask_texels, float4 bounds_lo, \
      float4 bounds_hi

#define MBAO_SCENE_VIEW()                                                                              \
  ((SceneView){kd_nodes, (__global const uint*)kd_nodes, triangles, triangle_vertices, vertex_normals, \
               triangle_masks, masked_triangles, mask_textures, mask_texels, bounds_lo.xyz, bounds_hi.xyz})

static inline float3 triangle_corner(const SceneView* scene, uint triangle, int corner) {
  __global const float* along = (__global const float*)scene->triangles[triangle].along;
  return (float3)(along[corner], along[4 + corner], along[8 + corner]);
}

// Whether a hit at barycentrics (b1, b2) of `triangle` is solid: false where an
// alpha mask cuts the surface away (for every kind of ray).
static inline int hit_is_solid(const SceneView* scene, uint triangle, float b1, float b2) {
#if MBAO_ALPHA_MASKS
  const uint slot = scene->triangle_masks[triangle];
  if (slot == MBAO_NOT_MASKED) return 1;
  const MaskedTriangle masked = scene->masked_triangles[slot];
  return mask_is_opaque(masked, scene->mask_textures[masked.texture], scene->mask_texels, b1, b2);
#else
  return 1;
#endif
}

#endif
