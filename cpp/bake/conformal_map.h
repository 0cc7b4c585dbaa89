// A chart of generated UVs laid flat by a least-squares conformal map (Lévy,
// Petitjean, Ray and Maillot 2002, SPEC 6.3): of all the ways to lay the
// triangles flat with their shared corners shared, the one that keeps their
// angles best. A curved chart (a helmet's dome, a column's drum) then lies
// flat with its texels nearly square, where projecting it onto a plane
// squeezes the triangles that tilt from it.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace mbao {

struct ConformalChart {
  std::vector<glm::dvec2> corners;  // three per triangle, in world units
  // The largest factor by which the map lengthens or shortens a direction in
  // any of the triangles (1 where it keeps every length), the scale chosen to
  // make it least.
  double stretch = 1.0;
  std::vector<std::uint32_t> overlapping;  // the triangles that overlap one before them, in order
};

// `corners[3 t + k]`, the positions of triangle t's corners, laid flat,
// `ids[3 t + k]` naming each corner's vertex so that triangles sharing a vertex
// share its place in the plane. None where the map turns a triangle over or
// stretches one by more than `max_stretch`. The triangles must have area and
// join across edges, as a chart's do.
std::optional<ConformalChart> conformal_map(const std::vector<glm::dvec3>& corners,
                                            const std::vector<std::uint32_t>& ids, double max_stretch);

}  // namespace mbao
