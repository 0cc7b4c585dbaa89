// The scene as the kernels see it: the kd-tree, the triangles it indexes and,
// only when shading normals are used, the vertex normals.
#ifndef MBAO_SCENE_H
#define MBAO_SCENE_H

#include "mbao/kd_node.h"
#include "geometry.h"

typedef struct SceneView {
  __global const KdNode* nodes;
  __global const uint* leaf_triangles;     // triangle ids, leaf by leaf
  __global const float4* triangle_corners;  // 3 per triangle, world space
  __global const uint* triangle_vertices;  // 3 vertex ids per triangle (only with normals)
  __global const float4* vertex_normals;   // NULL: geometric normals everywhere
  float3 bounds_lo, bounds_hi;
} SceneView;

// Every kernel that traces takes the scene as its first parameters, in this order.
#define MBAO_SCENE_PARAMS                                                              \
  __global const KdNode *kd_nodes, __global const uint *leaf_triangles,                 \
      __global const float4 *triangle_corners, __global const uint *triangle_vertices, \
      __global const float4 *vertex_normals, float4 bounds_lo, float4 bounds_hi

static inline SceneView make_scene_view(__global const KdNode* kd_nodes,
                                        __global const uint* leaf_triangles,
                                        __global const float4* triangle_corners,
                                        __global const uint* triangle_vertices,
                                        __global const float4* vertex_normals, float4 bounds_lo,
                                        float4 bounds_hi) {
  SceneView scene;
  scene.nodes = kd_nodes;
  scene.leaf_triangles = leaf_triangles;
  scene.triangle_corners = triangle_corners;
  scene.triangle_vertices = triangle_vertices;
  scene.vertex_normals = vertex_normals;
  scene.bounds_lo = bounds_lo.xyz;
  scene.bounds_hi = bounds_hi.xyz;
  return scene;
}

#define MBAO_SCENE_VIEW()                                                                     \
  make_scene_view(kd_nodes, leaf_triangles, triangle_corners, triangle_vertices, vertex_normals, \
                  bounds_lo, bounds_hi)

static inline float3 triangle_corner(const SceneView* scene, uint triangle, int corner) {
  return scene->triangle_corners[3 * triangle + corner].xyz;
}

#endif
