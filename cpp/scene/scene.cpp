#include "scene/scene.h"

namespace mbao {
namespace {

std::uint64_t next_scene_id() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

}  // namespace

Scene::Scene(TriangleMesh mesh, std::string name, std::optional<Camera> camera, std::vector<std::string> warnings)
    : mesh_(std::move(mesh)),
      name_(std::move(name)),
      camera_(std::move(camera)),
      warnings_(std::move(warnings)),
      id_(next_scene_id()) {
  mesh_.validate(name_);
  bounds_ = mesh_.bounds();
}

Camera Scene::default_camera(float aspect) const { return camera_ ? *camera_ : Camera::framing(bounds_, aspect); }

std::shared_ptr<const KdTree> Scene::kd_tree() const {
  std::lock_guard<std::mutex> lock(tree_mutex_);
  if (!tree_) tree_ = std::make_shared<const KdTree>(build_kd_tree(mesh_));
  return tree_;
}

bool Scene::has_kd_tree() const {
  std::lock_guard<std::mutex> lock(tree_mutex_);
  return tree_ != nullptr;
}

}  // namespace mbao
