#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "accel/kd_tree.h"
#include "scene/alpha_masks.h"
#include "scene/camera.h"
#include "scene/triangle_mesh.h"
#include "scene/uv_sets.h"

namespace mbao {

// Geometry ready to render: the mesh, its alpha masks, the camera it came with
// (if any) and its kd-tree, built on first use and kept for every later render.
class Scene {
 public:
  // Throws std::invalid_argument (naming `name`) for a mesh or masks that cannot be rendered.
  Scene(TriangleMesh mesh, std::string name, std::optional<Camera> camera = std::nullopt,
        std::vector<std::string> warnings = {}, AlphaMasks masks = {}, UvSets uv_sets = {});
  virtual ~Scene() = default;
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  const TriangleMesh& mesh() const { return *mesh_; }
  // The mesh, for what reads it in place and must keep it (a device that
  // shares host memory reads its vertices and indices).
  std::shared_ptr<const TriangleMesh> shared_mesh() const { return mesh_; }
  const AlphaMasks& masks() const { return masks_; }
  // What a texture bake reads; uv_sets().loaded only where the loader was asked for them.
  const UvSets& uv_sets() const { return uv_sets_; }
  const Bounds3& bounds() const { return bounds_; }
  // The point the device's coordinates are relative to. On each axis where the
  // scene lies farther from 0 than it is wide, its near edge (a vertex
  // coordinate, so that every vertex moves exactly, Sterbenz's lemma); on the
  // others 0, where world coordinates are already as fine as the scene's size
  // allows. Rounding in ray/triangle tests and in the offset of rays leaving a
  // surface then scales with the scene's size, not its distance from the world
  // origin, so a scene renders the same wherever it is placed.
  const glm::vec3& render_origin() const { return render_origin_; }
  const std::string& name() const { return name_; }
  const std::optional<Camera>& camera() const { return camera_; }
  // What the loader skipped or repaired, and a scene placed too far from the
  // origin for float32 (see render_origin), one sentence each.
  const std::vector<std::string>& warnings() const { return warnings_; }
  // Unique for the life of the process: names the scene in device caches.
  std::uint64_t id() const { return id_; }

  // Its own camera, else one that frames the bounds at this width/height ratio.
  Camera default_camera(float aspect) const;

  // Built on the first call. A build whose nodes pass max_bytes stops with
  // KdTreeTooLarge and leaves no tree: a later call builds again.
  std::shared_ptr<const KdTree> kd_tree(std::size_t max_bytes = std::numeric_limits<std::size_t>::max()) const;
  bool has_kd_tree() const;
  // How kd_tree() builds the tree. Only before it is built: throws std::logic_error after.
  void set_kd_build_options(const KdBuildOptions& options);

 private:
  std::shared_ptr<const TriangleMesh> mesh_;
  AlphaMasks masks_;
  UvSets uv_sets_;
  Bounds3 bounds_;
  glm::vec3 render_origin_;
  std::string name_;
  std::optional<Camera> camera_;
  std::vector<std::string> warnings_;
  std::uint64_t id_;
  KdBuildOptions kd_build_options_;
  mutable std::mutex tree_mutex_;
  mutable std::shared_ptr<const KdTree> tree_;
};

// A scene made directly from arrays: no camera, no file.
class Mesh : public Scene {
 public:
  explicit Mesh(TriangleMesh mesh) : Scene(std::move(mesh), "mesh") {}
};

}  // namespace mbao
