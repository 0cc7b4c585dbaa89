#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

#include "mbao/limits.h"

namespace mbao {

enum class Estimator { Branching, Path };
enum class NormalMode { Shading, Geometric };
// Auto: the fastest measured for the device's type (see traversal_for).
enum class Traversal { Restart, PushDown, ShortStack, Stack, Auto };

// Names as the Python API spells them; parse_* throw std::invalid_argument
// listing the allowed names.
Estimator parse_estimator(const std::string& name);
NormalMode parse_normal_mode(const std::string& name);
Traversal parse_traversal(const std::string& name);
std::string to_string(Estimator estimator);
std::string to_string(NormalMode mode);
std::string to_string(Traversal traversal);

// Everything a render is asked for besides the scene and the camera (SPEC 1-2).
struct RenderSettings {
  // 64-bit so that any integer a caller passes reaches validate() unchanged.
  std::int64_t width = 512;
  std::int64_t height = 512;
  std::int64_t bounces = 1;
  std::int64_t samples = 4;  // r: directions per hit
  Estimator estimator = Estimator::Branching;
  float rho = 1.0f;
  float max_distance = std::numeric_limits<float>::infinity();
  std::int64_t spp = 1;
  NormalMode normals = NormalMode::Shading;
  std::uint64_t seed = 0;
  Traversal traversal = Traversal::Auto;
  bool count_traversal = false;  // build the kernels that count nodes, leaves, triangle tests and restarts
  // How the work is cut up; neither changes the image.
  std::size_t tile_pixels = 0;      // pixels per launch; 0 picks a size that bounds memory
  std::size_t work_group_size = 0;  // 0 lets the OpenCL driver choose

  // Throws std::invalid_argument naming the first bad setting and its allowed range.
  void validate() const;
  // Upper bound on the AO rays of one camera sample: r + ... + r^b or r * b.
  std::uint64_t max_rays_per_camera_sample() const;
};

// The largest bounce count of the branching estimator; the path estimator has no such limit.
constexpr std::int64_t kMaxBranchingBounces = MBAO_MAX_BRANCHING_BOUNCES;

}  // namespace mbao
