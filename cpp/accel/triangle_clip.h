#pragma once

#include <array>
#include <glm/vec3.hpp>
#include <optional>

#include "scene/bounds.h"

namespace mbao {

// The box around the part of a triangle inside a closed cell, or nothing when
// the triangle misses the cell ("perfect splits", Havran 2000). Conservative:
// clipping runs in double against planes moved out by a hair, and the result
// is rounded outward to float and clamped to the cell, so a triangle that
// touches the cell is never dropped and its box never misses part of it.
std::optional<Bounds3> clipped_bounds(const std::array<glm::vec3, 3>& triangle, const Bounds3& cell);

// clipped_bounds of the triangle in each of the two cells that a split along
// `axis` made of one (below, above), clipping to the walls they share once.
std::array<std::optional<Bounds3>, 2> clipped_bounds_of_split(const std::array<glm::vec3, 3>& triangle,
                                                              const Bounds3& below, const Bounds3& above, int axis);

}  // namespace mbao
