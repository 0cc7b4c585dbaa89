#include "scene/scene.h"

namespace mbao {
namespace {

std::uint64_t next_scene_id() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

void validate_masks(const AlphaMasks& masks, std::size_t triangle_count, const std::string& name) {
  if (masks.empty()) return;
  if (masks.triangle_mask.size() != triangle_count)
    throw std::invalid_argument(name + ": alpha masks cover " + std::to_string(masks.triangle_mask.size()) +
                                " triangles of " + std::to_string(triangle_count));
  for (std::uint32_t slot : masks.triangle_mask)
    if (slot != MBAO_NOT_MASKED && slot >= masks.triangles.size())
      throw std::invalid_argument(name + ": alpha mask slot " + std::to_string(slot) + " does not exist");
  for (const MaskedTriangle& t : masks.triangles)
    if (t.texture >= masks.textures.size())
      throw std::invalid_argument(name + ": masked triangle uses missing texture " + std::to_string(t.texture));
  for (const MaskTexture& t : masks.textures)
    if (t.width == 0 || t.height == 0 || std::uint64_t(t.first_texel) + std::uint64_t(t.width) * t.height > masks.texels.size())
      throw std::invalid_argument(name + ": an alpha texture lies outside the texel data");
}

}  // namespace

Scene::Scene(TriangleMesh mesh, std::string name, std::optional<Camera> camera, std::vector<std::string> warnings,
             AlphaMasks masks)
    : mesh_(std::move(mesh)),
      masks_(std::move(masks)),
      name_(std::move(name)),
      camera_(std::move(camera)),
      warnings_(std::move(warnings)),
      id_(next_scene_id()) {
  bounds_ = mesh_.checked_bounds(name_);
  validate_masks(masks_, mesh_.triangles.size(), name_);
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
