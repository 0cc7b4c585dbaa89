#include "render/device_scene.h"

#include <algorithm>
#include <iomanip>
#include <sstream>
#include <string>

#include "core/error.h"
#include "opencl/launch.h"
#include "render/render_plan.h"

namespace mbao {
namespace {

cl_float4 to_float4(const glm::vec3& v) { return {{v.x, v.y, v.z, 0.0f}}; }

std::string in_units(std::size_t bytes) {
  if (bytes < (std::size_t(1) << 20)) return std::to_string(bytes) + " bytes";
  const bool gib = bytes >= (std::size_t(1) << 30);
  std::ostringstream text;
  text << std::fixed << std::setprecision(2) << double(bytes) / double(gib ? 1ull << 30 : 1ull << 20)
       << (gib ? " GiB" : " MiB");
  return text.str();
}

// Throws where `bytes` for `what` of `scene` pass `limit`, the largest buffer of `device_name`.
void check_buffer(std::size_t bytes, std::size_t limit, const std::string& device_name, const Scene& scene,
                  const std::string& what) {
  if (bytes <= limit) return;
  const std::size_t triangles = scene.mesh().triangles.size();
  const std::size_t fit = std::size_t(double(triangles) * double(limit) / double(bytes));
  throw DeviceError(scene.name() + ": its " + what + " need one device buffer of " + in_units(bytes) + " (" +
                    std::to_string(triangles) + " triangles), more than the " + in_units(limit) + " that " +
                    device_name + " allocates at most (CL_DEVICE_MAX_MEM_ALLOC_SIZE): about " + std::to_string(fit) +
                    " triangles fit");
}

std::size_t largest_buffer(const cl::Device& device) { return device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>(); }

}  // namespace

std::shared_ptr<const KdTree> DeviceScene::tree_within(const Scene& scene, const cl::Device& device) {
  return tree_within(scene, largest_buffer(device), device.getInfo<CL_DEVICE_NAME>());
}

std::shared_ptr<const KdTree> DeviceScene::tree_within(const Scene& scene, std::size_t limit,
                                                       const std::string& device_name) {
  try {
    return scene.kd_tree(limit);
  } catch (const KdTreeTooLarge& e) {
    const std::size_t triangles = scene.mesh().triangles.size();
    const std::size_t fit = std::size_t(double(triangles) * double(limit) / double(e.bytes_written));
    throw DeviceError(scene.name() + ": its kd-tree's nodes need one device buffer of more than " +
                      in_units(e.bytes_written) + " (" + std::to_string(triangles) + " triangles; the build stopped" +
                      " there), more than the " + in_units(limit) + " that " + device_name +
                      " allocates at most (CL_DEVICE_MAX_MEM_ALLOC_SIZE): fewer than " + std::to_string(fit) +
                      " triangles fit");
  }
}

void DeviceScene::check_fits(const Scene& scene, const cl::Device& device, bool with_normals, bool indexed_triangles) {
  check_fits(scene, largest_buffer(device), device.getInfo<CL_DEVICE_NAME>(), with_normals, indexed_triangles);
}

void DeviceScene::check_fits(const Scene& scene, std::size_t limit, const std::string& device_name, bool with_normals,
                             bool indexed_triangles) {
  const TriangleMesh& mesh = scene.mesh();
  const std::size_t triangles = mesh.triangles.size();
  if (indexed_triangles) {
    check_buffer(mesh.positions.size() * sizeof(glm::vec3), limit, device_name, scene, "vertex positions");
  } else {
    check_buffer(triangles * 3 * sizeof(cl_float4), limit, device_name, scene, "triangles' corners");
  }
  if (indexed_triangles || (with_normals && mesh.has_normals()))
    check_buffer(triangles * 3 * sizeof(cl_uint), limit, device_name, scene, "triangles' vertex indices");
  if (with_normals && mesh.has_normals())
    check_buffer(mesh.normals.size() * sizeof(cl_float4), limit, device_name, scene, "vertex normals");
  const AlphaMasks& masks = scene.masks();
  check_buffer(masks.triangle_mask.size() * sizeof(std::uint32_t), limit, device_name, scene, "triangles' masks");
  check_buffer(masks.triangles.size() * sizeof(MaskedTriangle), limit, device_name, scene, "masked triangles");
  check_buffer(masks.texels.size(), limit, device_name, scene, "alpha mask texels");
}

template <typename T>
cl::Buffer DeviceScene::upload(const cl::Context& context, cl::CommandQueue& queue, const std::vector<T>& data) {
  const std::size_t size = data.size() * sizeof(T);
  // OpenCL has no empty buffers; an empty list still gets one element.
  cl::Buffer buffer(context, CL_MEM_READ_ONLY, std::max<std::size_t>(size, sizeof(T)));
  if (size) queue.enqueueWriteBuffer(buffer, CL_TRUE, 0, size, data.data());  // blocking: data is a temporary
  bytes_ += std::max<std::size_t>(size, sizeof(T));
  return buffer;
}

template <typename T, typename Fill>
cl::Buffer DeviceScene::upload_filled(const cl::Context& context, cl::CommandQueue& queue, std::size_t count,
                                      const Fill& fill) {
  const std::size_t size = std::max<std::size_t>(count, 1) * sizeof(T);
  cl::Buffer buffer(context, CL_MEM_READ_ONLY, size);
  auto* items = static_cast<T*>(queue.enqueueMapBuffer(buffer, CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, size));
  fill(items);
  queue.enqueueUnmapMemObject(buffer, items);
  bytes_ += size;
  return buffer;
}

template <typename T>
cl::Buffer DeviceScene::in_place(const cl::Context& context, const std::vector<T>& data) {
  const std::size_t size = data.size() * sizeof(T);  // a scene has triangles, and a tree a root
  bytes_ += size;
  // Read only, so the const_cast hands OpenCL nothing it writes.
  return cl::Buffer(context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, size, const_cast<T*>(data.data()));
}

DeviceScene::DeviceScene(const cl::Context& context, cl::CommandQueue& queue, const Scene& scene,
                         std::shared_ptr<const KdTree> tree, bool with_normals, bool shares_host_memory,
                         bool indexed_triangles)
    : tree_(std::move(tree)), indexed_triangles_(indexed_triangles) {
  const TriangleMesh& mesh = scene.mesh();
  const glm::vec3 origin = scene.render_origin();  // the tree's frame
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::uvec3) == 3 * sizeof(cl_uint),
                "the kernels read the mesh's vertices and indices as packed triples");
  try {
    const cl::Device device = queue.getInfo<CL_QUEUE_DEVICE>();
    check_buffer(tree_->nodes.size() * sizeof(KdNode), largest_buffer(device), device.getInfo<CL_DEVICE_NAME>(), scene,
                 "kd-tree's nodes");
    nodes_ = shares_host_memory ? in_place(context, tree_->nodes) : upload(context, queue, tree_->nodes);
    if (indexed_triangles) {
      if (!shares_host_memory) throw std::logic_error("indexed triangles are read in place, from host memory");
      mesh_ = scene.shared_mesh();
      vertex_positions_ = in_place(context, mesh_->positions);
      triangle_vertices_ = in_place(context, mesh_->triangles);
    } else {
      // Per triangle and axis, its corners' coordinates (TriangleCoordinates in kernels/geometry.h).
      triangles_ = upload_filled<cl_float4>(context, queue, mesh.triangles.size() * 3, [&](cl_float4* out) {
        for (const glm::uvec3& t : mesh.triangles) {
          glm::vec3 p[3];
          for (int k = 0; k < 3; ++k) p[k] = mesh.positions[t[k]] - origin;
          for (int axis = 0; axis < 3; ++axis) *out++ = {{p[0][axis], p[1][axis], p[2][axis], 0.0f}};
        }
      });
    }
    if (with_normals) upload_normals(context, queue, mesh);
    const AlphaMasks& masks = scene.masks();
    if (!masks.empty()) {
      triangle_masks_ = upload(context, queue, masks.triangle_mask);
      masked_triangles_ = upload(context, queue, masks.triangles);
      mask_textures_ = upload(context, queue, masks.textures);
      mask_texels_ = upload(context, queue, masks.texels);
    }
  } catch (const cl::Error& e) {
    throw_device_error("uploading " + scene.name() + " (" + std::to_string(mesh.triangles.size()) + " triangles)", e);
  }
  bounds_lo_ = to_float4(tree_->bounds.lo);
  bounds_hi_ = to_float4(tree_->bounds.hi);
  render_origin_ = to_float4(origin);
}

DeviceScene::DeviceScene(const DeviceScene& other, const cl::Context& context, cl::CommandQueue& queue,
                         const Scene& scene, bool with_normals)
    : DeviceScene(other) {
  vertex_normals_ = cl::Buffer();
  if (!indexed_triangles_) triangle_vertices_ = cl::Buffer();
  bytes_ -= normal_bytes_;
  normal_bytes_ = 0;
  if (!with_normals) return;
  try {
    upload_normals(context, queue, scene.mesh());
  } catch (const cl::Error& e) {
    throw_device_error("uploading the vertex normals of " + scene.name(), e);
  }
}

void DeviceScene::upload_normals(const cl::Context& context, cl::CommandQueue& queue, const TriangleMesh& mesh) {
  if (!mesh.has_normals()) return;
  const std::size_t before = bytes_;
  if (!indexed_triangles_)
    triangle_vertices_ = upload_filled<cl_uint>(context, queue, mesh.triangles.size() * 3, [&](cl_uint* out) {
      for (const glm::uvec3& t : mesh.triangles) out = std::copy_n(&t.x, 3, out);
    });
  vertex_normals_ = upload_filled<cl_float4>(context, queue, mesh.normals.size(), [&](cl_float4* out) {
    for (const glm::vec3& n : mesh.normals) *out++ = to_float4(n);
  });
  normal_bytes_ = bytes_ - before;
}

void DeviceScene::append_to(KernelArgs& args) const {
  // A buffer the scene does not need is NULL in the kernel.
  for (const cl::Buffer* buffer : {&nodes_, &triangles_, &vertex_positions_, &triangle_vertices_, &vertex_normals_,
                                   &triangle_masks_, &masked_triangles_, &mask_textures_, &mask_texels_})
    args.append(*buffer);
  args.append(bounds_lo_);
  args.append(bounds_hi_);
  args.append(render_origin_);
}

std::shared_ptr<const DeviceScene> DeviceSceneCache::get(ComputeContext& compute,
                                                         const std::shared_ptr<const Scene>& scene, bool with_normals,
                                                         bool indexed_triangles) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = entries_.begin(); it != entries_.end();) it = it->second.scene.expired() ? entries_.erase(it) : ++it;
  Entry& entry = entries_[{scene->id(), with_normals}];
  if (!entry.device_scene) {
    // The scene with the other choice of normals has the rest already.
    const auto other = entries_.find({scene->id(), !with_normals});
    entry.device_scene = other != entries_.end() && other->second.device_scene
                             ? std::make_shared<const DeviceScene>(*other->second.device_scene, compute.context(),
                                                                   compute.queue(), *scene, with_normals)
                             : std::make_shared<const DeviceScene>(
                                   compute.context(), compute.queue(), *scene, scene->kd_tree(), with_normals,
                                   device_profile(compute.device()).shares_host_memory, indexed_triangles);
    entry.scene = scene;
  }
  return entry.device_scene;
}

}  // namespace mbao
