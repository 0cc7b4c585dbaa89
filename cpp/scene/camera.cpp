#include "scene/camera.h"

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "core/error.h"

namespace mbao {
namespace {

bool is_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// target - eye in double, where lengths and cross products of float vectors
// neither overflow nor underflow: in float, a camera 1e19 from its target (or
// with up that long) squares to infinity, one 1e-30 from it to zero.
glm::dvec3 view_direction(const Camera& camera) { return glm::dvec3(camera.target) - glm::dvec3(camera.eye); }

glm::vec3 read_vec3(const nlohmann::json& doc, const char* key, const std::string& path) {
  const auto it = doc.find(key);
  if (it == doc.end()) throw LoadError(path + ": \"" + key + "\" is missing");
  if (!it->is_array() || it->size() != 3 || !(*it)[0].is_number() || !(*it)[1].is_number() || !(*it)[2].is_number())
    throw LoadError(path + ": \"" + key + "\" must be an array of 3 numbers");
  return {(*it)[0].get<float>(), (*it)[1].get<float>(), (*it)[2].get<float>()};
}

float read_number(const nlohmann::json& doc, const char* key, const std::string& path) {
  const auto it = doc.find(key);
  if (it == doc.end()) throw LoadError(path + ": \"" + key + "\" is missing");
  if (!it->is_number()) throw LoadError(path + ": \"" + key + "\" must be a number");
  return it->get<float>();
}

}  // namespace

Camera Camera::load(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw LoadError(path + ": cannot open camera file");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(file);
  } catch (const nlohmann::json::parse_error& e) {
    throw LoadError(path + ": not valid JSON (" + e.what() + ")");
  }
  if (!doc.is_object()) throw LoadError(path + ": expected a JSON object");
  Camera camera;
  camera.eye = read_vec3(doc, "eye", path);
  camera.target = read_vec3(doc, "target", path);
  camera.up = read_vec3(doc, "up", path);
  camera.vfov_deg = read_number(doc, "vfov_deg", path);
  if (doc.contains("max_distance")) camera.max_distance = read_number(doc, "max_distance", path);
  try {
    camera.validate();
  } catch (const std::invalid_argument& e) {
    throw LoadError(path + ": " + e.what());
  }
  return camera;
}

Camera Camera::framing(const Bounds3& bounds, float aspect) {
  Camera camera;
  camera.vfov_deg = 45.0f;
  const glm::vec3 center = bounds.center();
  const float radius = std::max(0.5f * glm::length(bounds.extent()), 1e-6f);
  const float half_v = glm::radians(camera.vfov_deg) / 2.0f;
  const float half_h = std::atan(std::tan(half_v) * aspect);
  const float distance = radius / std::sin(std::min(half_v, half_h));
  const glm::vec3 view_from = glm::normalize(glm::vec3(0.35f, 0.4f, 1.0f));
  camera.eye = center + distance * view_from;
  camera.target = center;
  return camera;
}

void Camera::validate() const {
  if (!is_finite(eye) || !is_finite(target) || !is_finite(up))
    throw std::invalid_argument("camera: eye, target and up must be finite");
  if (!(vfov_deg > 0.0f && vfov_deg < 180.0f))
    throw std::invalid_argument("camera: vfov_deg must be in (0, 180), got " + std::to_string(vfov_deg));
  const glm::dvec3 forward = view_direction(*this);
  if (glm::length(forward) == 0.0) throw std::invalid_argument("camera: eye and target are the same point");
  const glm::dvec3 side = glm::cross(glm::normalize(forward), glm::dvec3(up));
  if (!(glm::length(side) > 1e-6 * glm::length(glm::dvec3(up))))
    throw std::invalid_argument("camera: up is zero or parallel to the view direction (target - eye)");
  if (max_distance && !(*max_distance > 0.0f)) throw std::invalid_argument("camera: max_distance must be > 0");
}

Camera Camera::relative_to(const glm::vec3& origin) const {
  Camera moved = *this;
  moved.eye -= origin;
  moved.target -= origin;
  return moved;
}

CameraBasis::CameraBasis(const Camera& camera)
    : tan_half_vfov(static_cast<float>(std::tan(glm::radians(double(camera.vfov_deg)) / 2.0))) {
  const glm::dvec3 view_forward = glm::normalize(view_direction(camera));
  const glm::dvec3 view_right = glm::normalize(glm::cross(view_forward, glm::dvec3(camera.up)));
  forward = glm::vec3(view_forward);
  right = glm::vec3(view_right);
  up = glm::vec3(glm::cross(view_right, view_forward));
}

glm::vec3 CameraBasis::direction(float px, float py, int width, int height) const {
  const float u = (px / float(width)) * 2.0f - 1.0f;
  const float v = 1.0f - (py / float(height)) * 2.0f;
  const float aspect = float(width) / float(height);
  return glm::normalize(forward + u * tan_half_vfov * aspect * right + v * tan_half_vfov * up);
}

}  // namespace mbao
