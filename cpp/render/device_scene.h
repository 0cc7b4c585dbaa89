#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "opencl/compute_context.h"
#include "opencl/kernel_args.h"
#include "scene/scene.h"

namespace mbao {

// A scene's kd-tree and triangles in device memory, in the order the kernels'
// MBAO_SCENE_PARAMS expect. Vertex normals are uploaded only when the render
// uses them, alpha masks only when the scene has them.
//
// A device that reads host memory (DeviceProfile::shares_host_memory: a CPU)
// reads the tree's nodes where they are (CL_MEM_USE_HOST_PTR), which this
// object keeps; any other device gets a copy. The triangles are 48 bytes of
// coordinates each, three loads for a test, or, where the plan says so
// (ProgramVariant::indexed_triangles, on such a device only), the mesh's own
// vertices and indices, read in place, from which the kernels assemble them.
class DeviceScene {
 public:
  DeviceScene(const cl::Context& context, cl::CommandQueue& queue, const Scene& scene,
              std::shared_ptr<const KdTree> tree, bool with_normals, bool shares_host_memory, bool indexed_triangles);
  // `other`'s scene with or without its vertex normals: the same buffers but
  // the normals, which are uploaded where `other` lacks them.
  DeviceScene(const DeviceScene& other, const cl::Context& context, cl::CommandQueue& queue, const Scene& scene,
              bool with_normals);

  // The scene's tree, built if need be, where the device can allocate its
  // nodes: a build that outgrows the largest buffer stops soon after with a
  // DeviceError naming the bytes, the limit and the device, and leaves no tree.
  static std::shared_ptr<const KdTree> tree_within(const Scene& scene, const cl::Device& device);
  // The same for a device named `device_name` that allocates at most `limit` bytes at once.
  static std::shared_ptr<const KdTree> tree_within(const Scene& scene, std::size_t limit,
                                                   const std::string& device_name);

  // Refuses, before its tree is built, a scene one of whose buffers the device
  // cannot allocate (CL_DEVICE_MAX_MEM_ALLOC_SIZE): a DeviceError naming the
  // buffer, its bytes, the limit, the device and the most triangles that fit.
  // The tree's nodes, known only once built, are checked as it is built (tree_within).
  static void check_fits(const Scene& scene, const cl::Device& device, bool with_normals, bool indexed_triangles);
  // The same for a device named `device_name` that allocates at most `limit` bytes at once.
  static void check_fits(const Scene& scene, std::size_t limit, const std::string& device_name, bool with_normals,
                         bool indexed_triangles);

  // The kernels' leading scene parameters (MBAO_SCENE_PARAMS), for set_kernel_args.
  void append_to(KernelArgs& args) const;
  std::size_t bytes() const { return bytes_; }
  // Whether the two hold the same tree and triangles' buffers, not copies.
  bool shares_geometry_with(const DeviceScene& other) const {
    return nodes_() == other.nodes_() && triangles_() == other.triangles_() &&
           vertex_positions_() == other.vertex_positions_();
  }

 private:
  template <typename T>
  cl::Buffer upload(const cl::Context& context, cl::CommandQueue& queue, const std::vector<T>& data);
  void upload_normals(const cl::Context& context, cl::CommandQueue& queue, const TriangleMesh& mesh);
  // A buffer over `data` itself, which the device reads in place.
  template <typename T>
  cl::Buffer in_place(const cl::Context& context, const std::vector<T>& data);
  // A buffer of `count` T that fill(T*) writes in place, through a map: the
  // items never exist as a whole in host memory besides the buffer.
  template <typename T, typename Fill>
  cl::Buffer upload_filled(const cl::Context& context, cl::CommandQueue& queue, std::size_t count, const Fill& fill);

  // What the device reads in place, kept as long as it may.
  std::shared_ptr<const KdTree> tree_;
  std::shared_ptr<const TriangleMesh> mesh_;
  bool indexed_triangles_ = false;
  cl::Buffer nodes_, triangles_, vertex_positions_, triangle_vertices_, vertex_normals_;
  cl::Buffer triangle_masks_, masked_triangles_, mask_textures_, mask_texels_;
  cl_float4 bounds_lo_{}, bounds_hi_{}, render_origin_{};
  std::size_t bytes_ = 0;
  std::size_t normal_bytes_ = 0;  // of bytes_, what only the normals need
};

// Uploads per (scene, normals) once per device, the two choices of normals
// sharing every other buffer; entries go when their scene does.
class DeviceSceneCache {
 public:
  // indexed_triangles: the plan's (the same for every render of a scene on a device).
  std::shared_ptr<const DeviceScene> get(ComputeContext& compute, const std::shared_ptr<const Scene>& scene,
                                         bool with_normals, bool indexed_triangles);

 private:
  struct Entry {
    std::weak_ptr<const Scene> scene;
    std::shared_ptr<const DeviceScene> device_scene;
  };
  std::mutex mutex_;
  std::map<std::pair<std::uint64_t, bool>, Entry> entries_;
};

}  // namespace mbao
