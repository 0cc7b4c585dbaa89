#include "bake/lightmap_uvs.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace mbao {
namespace {

// Vertices welded by equal position: glTF splits vertices at UV and normal
// seams, which must not split charts.
std::vector<std::uint32_t> welded_ids(const TriangleMesh& mesh) {
  struct Hash {
    std::size_t operator()(const glm::vec3& p) const {
      const glm::vec3 q = p + 0.0f;  // -0 to +0: equal positions hash equally
      std::uint32_t bits[3];
      std::memcpy(bits, &q, sizeof bits);
      return (std::size_t(bits[0]) * 73856093u) ^ (std::size_t(bits[1]) * 19349663u) ^ (std::size_t(bits[2]) * 83492791u);
    }
  };
  std::unordered_map<glm::vec3, std::uint32_t, Hash> ids;
  std::vector<std::uint32_t> welded(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    welded[v] = ids.emplace(mesh.positions[v], std::uint32_t(ids.size())).first->second;
  return welded;
}

struct Chart {
  std::vector<std::uint32_t> members;  // local triangle indices
  glm::dvec3 axis_u, axis_v;           // the plane it is projected onto
  glm::dvec2 lo, hi;                   // its bounds in that plane
};

// An orthonormal basis of the plane perpendicular to unit n (Duff et al. 2017).
void plane_axes(const glm::dvec3& n, glm::dvec3* u, glm::dvec3* v) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  *u = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
  *v = {b, sign + n.y * n.y * a, -n.y};
}

// Where each chart's box goes at `density` texels per unit: shelves filled left
// to right, tallest charts first, `padding` texels apart and from the border.
// Returns false where they do not fit.
bool pack(const std::vector<Chart>& charts, const std::vector<std::size_t>& tallest_first, double density, int width,
          int height, int padding, std::vector<glm::ivec2>* corners) {
  corners->assign(charts.size(), glm::ivec2(0));
  long long x = padding, y = padding, shelf = 0;
  for (std::size_t c : tallest_first) {
    const glm::dvec2 size = (charts[c].hi - charts[c].lo) * density;
    const long long w = (long long)std::ceil(size.x) + 1, h = (long long)std::ceil(size.y) + 1;
    if (x + w + padding > width) {
      x = padding;
      y += shelf + padding;
      shelf = 0;
    }
    if (x + w + padding > width || y + h + padding > height) return false;
    (*corners)[c] = glm::ivec2(int(x), int(y));
    x += w + padding;
    shelf = std::max(shelf, h);
  }
  return true;
}

// The triangles asked for: their unit normals, areas and neighbours.
struct Surface {
  std::vector<glm::dvec3> normals;
  std::vector<double> areas;
  std::vector<std::vector<std::uint32_t>> neighbours;  // local indices, across edges between equal positions
};

Surface surface_of(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles) {
  const std::size_t n = triangles.size();
  Surface s;
  s.normals.resize(n);
  s.areas.resize(n);
  s.neighbours.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::uvec3 t = mesh.triangles[triangles[i]];
    const glm::dvec3 p0(mesh.positions[t.x]), p1(mesh.positions[t.y]), p2(mesh.positions[t.z]);
    const glm::dvec3 c = glm::cross(p1 - p0, p2 - p0);
    s.areas[i] = 0.5 * glm::length(c);
    s.normals[i] = s.areas[i] > 0.0 ? c / (2.0 * s.areas[i]) : glm::dvec3(0.0);
  }
  const std::vector<std::uint32_t> welded = welded_ids(mesh);
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> edges;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!(s.areas[i] > 0.0)) continue;
    const glm::uvec3 t = mesh.triangles[triangles[i]];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = welded[t[k]], b = welded[t[(k + 1) % 3]];
      edges[{std::min(a, b), std::max(a, b)}].push_back(i);
    }
  }
  for (const auto& [edge, sharing] : edges)
    for (std::uint32_t i : sharing)
      for (std::uint32_t j : sharing)
        if (i != j) s.neighbours[i].push_back(j);
  return s;
}

// Charts grown from the largest triangles not yet taken; a triangle joins only
// charts of its own round (those that overlapped in a round start anew in the next).
std::vector<Chart> grow_charts(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                               const Surface& surface, const std::vector<int>& round, double* worst_stretch) {
  const std::size_t n = triangles.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return surface.areas[a] > surface.areas[b]; });
  std::vector<bool> taken(n, false);
  std::vector<Chart> charts;
  *worst_stretch = 1.0;
  for (std::uint32_t seed : order) {
    if (taken[seed] || !(surface.areas[seed] > 0.0)) continue;
    Chart chart;
    const glm::dvec3 axis = surface.normals[seed];
    plane_axes(axis, &chart.axis_u, &chart.axis_v);
    taken[seed] = true;
    chart.members.push_back(seed);
    for (std::size_t next = 0; next < chart.members.size(); ++next)
      for (std::uint32_t neighbour : surface.neighbours[chart.members[next]]) {
        if (taken[neighbour] || round[neighbour] != round[seed] ||
            glm::dot(surface.normals[neighbour], axis) < kChartCosine)
          continue;
        taken[neighbour] = true;
        chart.members.push_back(neighbour);
      }
    chart.lo = glm::dvec2(INFINITY);
    chart.hi = glm::dvec2(-INFINITY);
    for (std::uint32_t i : chart.members) {
      *worst_stretch = std::max(*worst_stretch, 1.0 / glm::dot(surface.normals[i], axis));
      const glm::uvec3 t = mesh.triangles[triangles[i]];
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 p(mesh.positions[t[k]]);
        const glm::dvec2 q(glm::dot(p, chart.axis_u), glm::dot(p, chart.axis_v));
        chart.lo = glm::min(chart.lo, q);
        chart.hi = glm::max(chart.hi, q);
      }
    }
    charts.push_back(std::move(chart));
  }
  return charts;
}

std::vector<std::size_t> tallest_first(const std::vector<Chart>& charts) {
  std::vector<std::size_t> order(charts.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return charts[a].hi.y - charts[a].lo.y > charts[b].hi.y - charts[b].lo.y;
  });
  return order;
}

// The least density tried: charts of more than 1e-270 world units still get boxes of 2 texels.
constexpr double kLeastDensity = 1e-30;

// Whether the charts fit at some density above 0, `padding` apart: each in a
// box of 2 x 2 texels (1 x 1 where it has no extent). At density 0 itself every
// chart would shrink to a point, which covers no texel.
bool fit_at_all(const std::vector<Chart>& charts, int width, int height, int padding) {
  std::vector<glm::ivec2> placed;
  return pack(charts, tallest_first(charts), kLeastDensity, width, height, padding, &placed);
}

// The largest padding up to `padding` at which the charts fit at all.
int fitting_padding(const std::vector<Chart>& charts, int width, int height, int padding) {
  for (int p = padding; p >= 0; --p)
    if (fit_at_all(charts, width, height, p)) return p;
  throw std::invalid_argument("generated UVs: " + std::to_string(charts.size()) + " charts do not fit " +
                              std::to_string(width) + " x " + std::to_string(height) +
                              " texels even at 2 x 2 texels each and touching; raise the resolution");
}

// The texture size, `width` x `height` times the least power of two, at which
// the charts fit `padding` apart; none up to kMaxTextureSide.
std::optional<glm::ivec2> size_keeping(const std::vector<Chart>& charts, int width, int height, int padding) {
  for (long long w = width, h = height; std::max(w, h) <= kMaxTextureSide; w *= 2, h *= 2)
    if (fit_at_all(charts, int(w), int(h), padding)) return glm::ivec2(int(w), int(h));
  return std::nullopt;
}

// The largest density at which the charts fit `padding` apart (they must fit
// at kLeastDensity), by bisection from the one at which their boxes' area alone would
// fill the texture, and where each goes.
double densest_packing(const std::vector<Chart>& charts, int width, int height, int padding,
                       std::vector<glm::ivec2>* placed) {
  const std::vector<std::size_t> order = tallest_first(charts);
  double box_area = 0.0;
  for (const Chart& c : charts) box_area += (c.hi.x - c.lo.x) * (c.hi.y - c.lo.y);
  double lo = kLeastDensity, hi = box_area > 0.0 ? std::sqrt(double(width) * double(height) / box_area) : 1.0;
  for (int step = 0; step < 40; ++step) {
    const double middle = 0.5 * (lo + hi);
    if (pack(charts, order, middle, width, height, padding, placed))
      lo = middle;
    else
      hi = middle;
  }
  pack(charts, order, lo, width, height, padding, placed);
  return lo;
}

std::vector<glm::vec2> chart_uvs(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                                 const std::vector<Chart>& charts, const std::vector<glm::ivec2>& placed,
                                 double density, int width, int height) {
  std::vector<glm::vec2> uvs(3 * triangles.size(), glm::vec2(0.0f));
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const Chart& chart = charts[c];
    // Half a texel in from the box's corner: the box is a texel larger than the chart.
    const glm::dvec2 origin = glm::dvec2(placed[c]) + 0.5;
    for (std::uint32_t i : chart.members) {
      const glm::uvec3 t = mesh.triangles[triangles[i]];
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 p(mesh.positions[t[k]]);
        const glm::dvec2 q =
            (glm::dvec2(glm::dot(p, chart.axis_u), glm::dot(p, chart.axis_v)) - chart.lo) * density + origin;
        uvs[3 * i + std::size_t(k)] = glm::vec2(q.x / width, q.y / height);
      }
    }
  }
  return uvs;
}

// Rounds of charts before giving up: each takes the triangles that overlapped
// in the round before out of their charts (a duplicate triangle, a chart that
// folds over itself); real assets need one or two.
constexpr int kMaxRounds = 8;

}  // namespace

LightmapUvs generate_lightmap_uvs(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles, int width,
                                  int height, int padding) {
  const Surface surface = surface_of(mesh, triangles);
  std::vector<int> round(triangles.size(), 0);
  for (int r = 0; r < kMaxRounds; ++r) {
    LightmapUvs result;
    const std::vector<Chart> charts = grow_charts(mesh, triangles, surface, round, &result.worst_stretch);
    std::vector<glm::ivec2> placed;
    result.padding = fitting_padding(charts, width, height, padding);
    if (result.padding < padding) result.size_keeping_padding = size_keeping(charts, width, height, padding);
    result.texels_per_unit = densest_packing(charts, width, height, result.padding, &placed);
    result.charts = charts.size();
    result.corner_uvs = chart_uvs(mesh, triangles, charts, placed, result.texels_per_unit, width, height);
    result.layout.emplace(mesh, triangles, result.corner_uvs, width, height, WrapMode::Repeat, WrapMode::Repeat);
    if (result.layout->second_claimants().empty()) return result;
    for (std::size_t i : result.layout->second_claimants()) round[i] = r + 1;
  }
  throw std::logic_error("generated UVs: charts still overlap after " + std::to_string(kMaxRounds) + " rounds");
}

}  // namespace mbao
