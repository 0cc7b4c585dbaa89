#pragma once

#include <glm/vec3.hpp>
#include <optional>
#include <string>

#include "scene/bounds.h"

namespace mbao {

// The pinhole camera of SPEC 3.1 (right-handed, Y up as in glTF).
struct Camera {
  glm::vec3 eye{0.0f};
  glm::vec3 target{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float vfov_deg = 60.0f;  // full vertical field of view
  // camera.json's suggested AO radius, when it has one (SPEC 3.1.1).
  std::optional<float> max_distance;

  // Reads camera.json; throws LoadError naming the file and the bad field.
  static Camera load(const std::string& path);
  // A camera that sees all of `bounds` at the given width/height ratio,
  // looking at its centre from the front, a little from the right and above.
  static Camera framing(const Bounds3& bounds, float aspect);

  // Throws std::invalid_argument for a camera that defines no view.
  void validate() const;
  // The same camera with `origin` as the origin of coordinates.
  Camera relative_to(const glm::vec3& origin) const;
};

// The orthonormal frame of SPEC 3.1, derived from a valid camera.
struct CameraBasis {
  glm::vec3 forward, right, up;
  float tan_half_vfov;

  explicit CameraBasis(const Camera& camera);
  // Direction through the image point (px, py), in pixels from the top-left corner.
  glm::vec3 direction(float px, float py, int width, int height) const;
};

}  // namespace mbao
