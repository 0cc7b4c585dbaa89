// The charts of generated UVs (SPEC 6.3): a material's triangles grown into
// charts and laid flat, projected onto planes or by conformal maps, for
// lightmap_uvs to cut and pack.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "bake/chart_packing.h"
#include "scene/triangle_mesh.h"

namespace mbao {

// Triangles join a projected chart while their normals fit a cone of
// half-angle acos(kChartCosine), about 37 degrees, around the axis it is
// projected along, so none is stretched by more than 1.25; a conformal chart
// is cut until none is.
constexpr double kChartCosine = 0.8;

// The triangles asked for: their unit normals, areas, neighbours and corners.
struct ChartSurface {
  std::vector<glm::dvec3> normals;
  std::vector<double> areas;
  std::vector<std::vector<std::uint32_t>> neighbours;  // local indices, across edges between equal positions
  std::vector<glm::dvec3> corners;                     // three per triangle
  std::vector<std::uint32_t> corner_ids;               // equal where corners' positions are
};

ChartSurface chart_surface(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles);

// A round's charts, each laid flat (a triangle joins only charts of its own
// round: those that overlapped in a round start anew in the next).
struct LaidCharts {
  std::vector<std::vector<std::uint32_t>> members;  // local indices
  std::vector<FlatChart> flat;
  std::vector<std::optional<glm::dvec3>> axes;  // a projected chart's; none where a conformal map laid it flat
  double worst_stretch = 1.0;  // the largest factor by which a chart lengthens or shortens a direction in a triangle
};

// Charts grown within a cone of half-angle acos(kChartCosine), each projected onto the plane perpendicular to its axis.
LaidCharts projected_charts(const ChartSurface& surface, const std::vector<int>& round);

// Each connected part of the round's triangles laid flat by a conformal map,
// cut in halves while it stretches a triangle by more than 1 / kChartCosine,
// and the pieces then merged in pairs where one conformal map still holds both.
LaidCharts conformal_charts(const ChartSurface& surface, const std::vector<int>& round);

// `members` projected onto the plane perpendicular to unit `axis`, turned.
FlatChart projected_flat(const ChartSurface& surface, const std::vector<std::uint32_t>& members,
                         const glm::dvec3& axis);

// The corners of `piece`, some of a chart's `members`, from its `flat`, turned anew.
FlatChart piece_flat(const std::vector<std::uint32_t>& members, const FlatChart& flat,
                     const std::vector<std::uint32_t>& piece);

// Pieces of a chart, cut apart by the triangles' centroids, with each
// triangle moved to the piece it shares the longest boundary with (by the
// length of the edges it shares), where that is longer than the one it shares
// with its own and its own keeps another triangle, until none moves. Each move
// shortens the cut: a straight cut through a fan of long thin triangles
// otherwise leaves spikes, whose gaps the packing cannot fill.
std::vector<std::vector<std::uint32_t>> shortened_cuts(const std::vector<std::vector<std::uint32_t>>& pieces,
                                                       const ChartSurface& surface);

// Each piece split where its triangles do not join across edges: a ring cut
// across leaves two arcs in a piece.
std::vector<std::vector<std::uint32_t>> connected_parts(const std::vector<std::vector<std::uint32_t>>& pieces,
                                                        const ChartSurface& surface);

}  // namespace mbao
