#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace mbao {
namespace {

// Float32 vertices lie on a grid whose spacing grows with their distance from
// the world origin. Past this spacing, as a fraction of the scene's size, the
// grid visibly changes the scene's shape and its AO (measured in
// tests/test_scale_and_placement.py); rendering relative to a point near it
// cannot undo rounding that happened before the vertices reached mbao.
constexpr float kMaxVertexSpacing = 1e-3f;

// The sizes across which the float32 ray/triangle test is exact: its edge
// functions multiply coordinates relative to the ray's origin, whose squares
// overflow float from about 1.8e19 and fall into denormals below about 1e-19.
// The Cornell box renders the same AO from 2e-18 to 8e18 across and silently
// wrong at 5.6e-20 and 5.6e19 (tests/test_scale_and_placement.py); the limits
// leave a margin for rays from outside the scene and for small triangles.
constexpr float kMinSceneSize = 1e-17f;
constexpr float kMaxSceneSize = 1e18f;

float largest(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

void check_extent(const Bounds3& box, const std::string& name) {
  const glm::vec3 extent = box.extent();
  if (!std::isfinite(extent.x) || !std::isfinite(extent.y) || !std::isfinite(extent.z))
    throw std::invalid_argument(name + ": the scene is wider than float32 can span (its bounds' extent overflows)");
  const float size = largest(extent);
  if (size > kMaxSceneSize || (size > 0.0f && size < kMinSceneSize)) {
    std::ostringstream message;
    message << name << ": the scene is " << size << " across; mbao's float32 ray tests are exact for scenes "
            << kMinSceneSize << " to " << kMaxSceneSize << " across: scale it into that range";
    throw std::invalid_argument(message.str());
  }
}

// Scene::render_origin: per axis, the near edge where the range lies within a
// factor 2 of it, so that p - edge is exact for every p in the range; else 0.
float exact_origin(float lo, float hi) {
  if (lo > 0.0f && hi <= 2.0f * lo) return lo;
  if (hi < 0.0f && lo >= 2.0f * hi) return hi;
  return 0.0f;
}

glm::vec3 exact_origin(const Bounds3& box) {
  return {exact_origin(box.lo.x, box.hi.x), exact_origin(box.lo.y, box.hi.y), exact_origin(box.lo.z, box.hi.z)};
}

std::vector<std::string> with_placement_warning(std::vector<std::string> warnings, const Bounds3& box,
                                                const std::string& name) {
  const float size = largest(box.extent());
  const float farthest = largest(glm::max(glm::abs(box.lo), glm::abs(box.hi)));
  const float spacing = std::nextafter(farthest, std::numeric_limits<float>::infinity()) - farthest;
  if (size > 0.0f && spacing > kMaxVertexSpacing * size) {
    std::ostringstream message;
    message << name << " is " << size << " across but lies up to " << farthest
            << " from the origin, where float32 vertex coordinates are " << spacing << " apart ("
            << 100.0f * spacing / size << "% of the scene): its shape is already rounded and its AO may be wrong. "
            << "Move it near the origin before its vertices become float32.";
    // Once: a scene made again from its own warnings (unpickled) already has it.
    if (std::find(warnings.begin(), warnings.end(), message.str()) == warnings.end()) warnings.push_back(message.str());
  }
  return warnings;
}

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
    if (t.width == 0 || t.height == 0 ||
        std::uint64_t(t.first_texel) + std::uint64_t(t.width) * t.height > masks.texels.size())
      throw std::invalid_argument(name + ": an alpha texture lies outside the texel data");
}

}  // namespace

Scene::Scene(TriangleMesh mesh, std::string name, std::optional<Camera> camera, std::vector<std::string> warnings,
             AlphaMasks masks, UvSets uv_sets)
    : mesh_(std::make_shared<const TriangleMesh>(std::move(mesh))),
      masks_(std::move(masks)),
      uv_sets_(std::move(uv_sets)),
      name_(std::move(name)),
      camera_(std::move(camera)),
      id_(next_scene_id()) {
  bounds_ = mesh_->checked_bounds(name_);
  check_extent(bounds_, name_);
  render_origin_ = exact_origin(bounds_);
  warnings_ = with_placement_warning(std::move(warnings), bounds_, name_);
  validate_masks(masks_, mesh_->triangles.size(), name_);
}

Camera Scene::default_camera(float aspect) const { return camera_ ? *camera_ : Camera::framing(bounds_, aspect); }

std::shared_ptr<const KdTree> Scene::kd_tree(std::size_t max_bytes) const {
  std::lock_guard<std::mutex> lock(tree_mutex_);
  if (tree_) return tree_;
  KdBuildOptions options = kd_build_options_;
  options.max_bytes = std::min(options.max_bytes, max_bytes);
  // In the device's frame.
  tree_ = std::make_shared<const KdTree>(build_kd_tree(*mesh_, options, render_origin_, masks_.triangle_mask));
  return tree_;
}

void Scene::set_kd_build_options(const KdBuildOptions& options) {
  std::lock_guard<std::mutex> lock(tree_mutex_);
  if (tree_) throw std::logic_error("scene " + name_ + ": its kd-tree is built already");
  kd_build_options_ = options;
}

bool Scene::has_kd_tree() const {
  std::lock_guard<std::mutex> lock(tree_mutex_);
  return tree_ != nullptr;
}

}  // namespace mbao
