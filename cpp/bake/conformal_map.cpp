#include "bake/conformal_map.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/SparseCholesky>
#include <glm/geometric.hpp>

namespace mbao {
namespace {

// Each corner's vertex numbered from 0, in order of first use.
std::vector<std::uint32_t> local_ids(const std::vector<std::uint32_t>& ids, std::size_t* vertices) {
  std::unordered_map<std::uint32_t, std::uint32_t> local;
  std::vector<std::uint32_t> numbered(ids.size());
  for (std::size_t c = 0; c < ids.size(); ++c)
    numbered[c] = local.emplace(ids[c], std::uint32_t(local.size())).first->second;
  *vertices = local.size();
  return numbered;
}

// A triangle in its own plane: corner 0 at the origin, corner 1 along x, counterclockwise.
struct PlaneTriangle {
  glm::dvec2 q[3];
  double area = 0.0;
};

PlaneTriangle in_own_plane(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2) {
  const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
  const glm::dvec3 x = glm::normalize(e1), y = glm::normalize(glm::cross(glm::cross(e1, e2), e1));
  PlaneTriangle t;
  t.q[0] = glm::dvec2(0.0);
  t.q[1] = glm::dvec2(glm::length(e1), 0.0);
  t.q[2] = glm::dvec2(glm::dot(e2, x), glm::dot(e2, y));
  t.area = 0.5 * t.q[1].x * t.q[2].y;
  return t;
}

// The two vertices to pin, far apart: the one farthest from the first corner, and the one farthest from that.
std::pair<std::uint32_t, std::uint32_t> far_apart(const std::vector<glm::dvec3>& positions) {
  const auto farthest_from = [&](const glm::dvec3& p) {
    std::uint32_t best = 0;
    for (std::uint32_t v = 1; v < positions.size(); ++v)
      if (glm::distance(positions[v], p) > glm::distance(positions[best], p)) best = v;
    return best;
  };
  const std::uint32_t a = farthest_from(positions[0]);
  return {a, farthest_from(positions[a])};
}

// The singular values of the 2 x 2 map taking a triangle's edges `from` to `to`, largest first.
std::pair<double, double> singular_values(const glm::dvec2 from[2], const glm::dvec2 to[2]) {
  const double det = from[0].x * from[1].y - from[1].x * from[0].y;
  // J = [to0 to1] * inverse([from0 from1]), column by column.
  const glm::dvec2 jx = (to[0] * from[1].y - to[1] * from[0].y) / det;
  const glm::dvec2 jy = (to[1] * from[0].x - to[0] * from[1].x) / det;
  const double conformal = std::hypot(0.5 * (jx.x + jy.y), 0.5 * (jx.y - jy.x));
  const double anticonformal = std::hypot(0.5 * (jx.x - jy.y), 0.5 * (jx.y + jy.x));
  return {conformal + anticonformal, std::abs(conformal - anticonformal)};
}

// Whether segments ab and cd cross at a point inside both (touching at an end is not crossing).
bool cross_properly(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d) {
  const auto side = [](const glm::dvec2& o, const glm::dvec2& p, const glm::dvec2& q) {
    return (p.x - o.x) * (q.y - o.y) - (p.y - o.y) * (q.x - o.x);
  };
  const double c_side = side(a, b, c), d_side = side(a, b, d), a_side = side(c, d, a), b_side = side(c, d, b);
  return ((c_side > 0.0 && d_side < 0.0) || (c_side < 0.0 && d_side > 0.0)) &&
         ((a_side > 0.0 && b_side < 0.0) || (a_side < 0.0 && b_side > 0.0));
}

// Whether p lies inside counterclockwise triangle t, not on its edges.
bool strictly_inside(const glm::dvec2& p, const glm::dvec2* t) {
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 a = t[k], b = t[(k + 1) % 3];
    if (!((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) > 0.0)) return false;
  }
  return true;
}

// Whether the interiors of two counterclockwise triangles meet: an edge of one crosses an edge of the
// other, or one's centroid lies inside the other (one holds the other, or they coincide).
bool interiors_meet(const glm::dvec2* a, const glm::dvec2* b) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (cross_properly(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3])) return true;
  return strictly_inside((a[0] + a[1] + a[2]) / 3.0, b) || strictly_inside((b[0] + b[1] + b[2]) / 3.0, a);
}

// The triangles (counterclockwise, three corners each) that overlap one before them, each tested against
// those in the cells of a grid its box covers.
std::vector<std::uint32_t> overlapping(const std::vector<glm::dvec2>& corners) {
  const std::size_t triangles = corners.size() / 3;
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  for (const glm::dvec2& c : corners) {
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  const auto cells = std::size_t(std::ceil(std::sqrt(double(triangles))));
  const glm::dvec2 cell_size = glm::max((hi - lo) / double(cells), glm::dvec2(1e-300));
  const auto cell_of = [&](const glm::dvec2& p) {
    return glm::min(glm::uvec2((p - lo) / cell_size), glm::uvec2(std::uint32_t(cells - 1)));
  };
  std::vector<std::vector<std::uint32_t>> grid(cells * cells);
  std::vector<std::uint32_t> found;
  for (std::uint32_t t = 0; t < triangles; ++t) {
    const glm::dvec2* corner = &corners[3 * t];
    const glm::uvec2 from = cell_of(glm::min(glm::min(corner[0], corner[1]), corner[2]));
    const glm::uvec2 to = cell_of(glm::max(glm::max(corner[0], corner[1]), corner[2]));
    bool overlaps = false;
    for (std::uint32_t y = from.y; y <= to.y && !overlaps; ++y)
      for (std::uint32_t x = from.x; x <= to.x && !overlaps; ++x)
        for (std::uint32_t other : grid[y * cells + x])
          if ((overlaps = interiors_meet(corner, &corners[3 * other]))) break;
    if (overlaps) {
      found.push_back(t);
      continue;
    }
    for (std::uint32_t y = from.y; y <= to.y; ++y)
      for (std::uint32_t x = from.x; x <= to.x; ++x) grid[y * cells + x].push_back(t);
  }
  return found;
}

}  // namespace

std::optional<ConformalChart> conformal_map(const std::vector<glm::dvec3>& corners,
                                            const std::vector<std::uint32_t>& ids, double max_stretch) {
  std::size_t n = 0;
  const std::vector<std::uint32_t> vertex = local_ids(ids, &n);
  const std::size_t triangles = corners.size() / 3;
  std::vector<glm::dvec3> positions(n);
  for (std::size_t c = 0; c < corners.size(); ++c) positions[vertex[c]] = corners[c];
  const auto [pin_a, pin_b] = far_apart(positions);
  // Unknowns u and v of every vertex but the pins; the pins' places go to the right-hand side.
  std::vector<int> unknown(n, -1);
  int unknowns = 0;
  for (std::uint32_t v = 0; v < n; ++v)
    if (v != pin_a && v != pin_b) unknown[v] = unknowns++;
  std::vector<glm::dvec2> place(n);
  place[pin_a] = glm::dvec2(0.0);
  place[pin_b] = glm::dvec2(glm::distance(positions[pin_a], positions[pin_b]), 0.0);

  // Per triangle, sqrt(area) times the Cauchy-Riemann residuals (v_x + u_y, v_y - u_x) of the linear map,
  // whose gradients are sums over corners of u_k and v_k times grad(barycentric k) = turn(opposite edge) / 2A.
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(Eigen::Index(2 * triangles));
  std::vector<PlaneTriangle> flat(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    flat[t] = in_own_plane(corners[3 * t], corners[3 * t + 1], corners[3 * t + 2]);
    const double weight = std::sqrt(flat[t].area), half_inverse_area = 0.5 / flat[t].area;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec2 edge = flat[t].q[(k + 2) % 3] - flat[t].q[(k + 1) % 3];
      const glm::dvec2 gradient = glm::dvec2(-edge.y, edge.x) * half_inverse_area * weight;
      const std::uint32_t v = vertex[3 * t + k];
      // Row 2t: gradient.y u + gradient.x v; row 2t + 1: -gradient.x u + gradient.y v.
      const auto row = Eigen::Index(2 * t);
      if (unknown[v] >= 0) {
        const Eigen::Index u_column = 2 * unknown[v], v_column = u_column + 1;
        entries.emplace_back(row, u_column, gradient.y);
        entries.emplace_back(row, v_column, gradient.x);
        entries.emplace_back(row + 1, u_column, -gradient.x);
        entries.emplace_back(row + 1, v_column, gradient.y);
      } else {
        rhs[row] -= gradient.y * place[v].x + gradient.x * place[v].y;
        rhs[row + 1] -= -gradient.x * place[v].x + gradient.y * place[v].y;
      }
    }
  }
  if (unknowns > 0) {
    Eigen::SparseMatrix<double> system(Eigen::Index(2 * triangles), 2 * unknowns);
    system.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SparseMatrix<double> normal = system.transpose() * system;
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
    if (solver.info() != Eigen::Success) return std::nullopt;
    const Eigen::VectorXd solution = solver.solve(system.transpose() * rhs);
    for (std::uint32_t v = 0; v < n; ++v)
      if (unknown[v] >= 0) place[v] = glm::dvec2(solution[2 * unknown[v]], solution[2 * unknown[v] + 1]);
  }

  // The scale that makes the worst stretch least: the geometric mean of the largest and smallest singular values.
  double largest = 0.0, smallest = INFINITY;
  for (std::size_t t = 0; t < triangles; ++t) {
    const glm::dvec2 a = place[vertex[3 * t]], b = place[vertex[3 * t + 1]], c = place[vertex[3 * t + 2]];
    const glm::dvec2 from[2] = {flat[t].q[1] - flat[t].q[0], flat[t].q[2] - flat[t].q[0]}, to[2] = {b - a, c - a};
    if (!(to[0].x * to[1].y - to[1].x * to[0].y > 0.0)) return std::nullopt;  // turned over, or collapsed
    const auto [high, low] = singular_values(from, to);
    largest = std::max(largest, high);
    smallest = std::min(smallest, low);
  }
  ConformalChart chart;
  chart.stretch = std::sqrt(largest / smallest);
  if (!(chart.stretch <= max_stretch)) return std::nullopt;
  const double scale = 1.0 / std::sqrt(largest * smallest);
  chart.corners.resize(corners.size());
  for (std::size_t c = 0; c < corners.size(); ++c) chart.corners[c] = place[vertex[c]] * scale;
  chart.overlapping = overlapping(chart.corners);
  return chart;
}

}  // namespace mbao
