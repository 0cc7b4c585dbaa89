#include "bake/uv_charts.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "bake/conformal_map.h"

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
      return (std::size_t(bits[0]) * 73856093u) ^ (std::size_t(bits[1]) * 19349663u) ^
             (std::size_t(bits[2]) * 83492791u);
    }
  };
  std::unordered_map<glm::vec3, std::uint32_t, Hash> ids;
  std::vector<std::uint32_t> welded(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    welded[v] = ids.emplace(mesh.positions[v], std::uint32_t(ids.size())).first->second;
  return welded;
}

// An orthonormal basis of the plane perpendicular to unit n (Duff et al. 2017).
void plane_axes(const glm::dvec3& n, glm::dvec3* u, glm::dvec3* v) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  *u = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
  *v = {b, sign + n.y * n.y * a, -n.y};
}

}  // namespace

ChartSurface chart_surface(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles) {
  const std::size_t n = triangles.size();
  ChartSurface s;
  s.normals.resize(n);
  s.areas.resize(n);
  s.neighbours.resize(n);
  const std::vector<std::uint32_t> welded = welded_ids(mesh);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::uvec3 t = mesh.triangles[triangles[i]];
    const glm::dvec3 p0(mesh.positions[t.x]), p1(mesh.positions[t.y]), p2(mesh.positions[t.z]);
    const glm::dvec3 c = glm::cross(p1 - p0, p2 - p0);
    s.areas[i] = 0.5 * glm::length(c);
    s.normals[i] = s.areas[i] > 0.0 ? c / (2.0 * s.areas[i]) : glm::dvec3(0.0);
    s.corners.insert(s.corners.end(), {p0, p1, p2});
    s.corner_ids.insert(s.corner_ids.end(), {welded[t.x], welded[t.y], welded[t.z]});
  }
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

namespace {

// A set of triangles whose unit normals all lie within `angle` of `axis`.
struct Cone {
  glm::dvec3 axis;
  double angle = 0.0;
};

double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// The narrowest cone around two cones: its axis on the arc between theirs.
Cone enclosing(const Cone& a, const Cone& b) {
  const double between = angle_between(a.axis, b.axis);
  if (between + b.angle <= a.angle) return a;
  if (between + a.angle <= b.angle) return b;
  const glm::dvec3 across = b.axis - glm::dot(b.axis, a.axis) * a.axis;  // towards b, perpendicular to a
  const double length = glm::length(across);
  if (!(length > 1e-9)) return {a.axis, std::max(a.angle, between + b.angle)};  // no direction to turn in
  const double angle = 0.5 * (between + a.angle + b.angle);
  const double from_a = angle - a.angle;  // in (0, between): neither holds the other
  return {std::cos(from_a) * a.axis + std::sin(from_a) * (across / length), angle};
}

// Charts grown from the largest triangles not yet taken across edges, each
// while the normals of its triangles fit a cone no wider than `widest` (its
// axis turning as it grows, which gives a third fewer charts on the helmet
// than a cone around the seed's normal); a triangle joins only charts of its
// own round (those that overlapped in a round start anew in the next).
std::vector<std::vector<std::uint32_t>> grown_charts(const ChartSurface& surface, const std::vector<int>& round,
                                                     double widest, std::vector<Cone>* cones) {
  const std::size_t n = surface.areas.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return surface.areas[a] > surface.areas[b]; });
  std::vector<bool> taken(n, false);
  std::vector<std::vector<std::uint32_t>> charts;
  for (std::uint32_t seed : order) {
    if (taken[seed] || !(surface.areas[seed] > 0.0)) continue;
    Cone cone{surface.normals[seed], 0.0};
    std::vector<std::uint32_t> members{seed};
    taken[seed] = true;
    for (std::size_t next = 0; next < members.size(); ++next)
      for (std::uint32_t neighbour : surface.neighbours[members[next]]) {
        if (taken[neighbour] || round[neighbour] != round[seed]) continue;
        const Cone wider = enclosing(cone, Cone{surface.normals[neighbour], 0.0});
        if (wider.angle > widest) continue;
        taken[neighbour] = true;
        members.push_back(neighbour);
        cone = wider;
      }
    charts.push_back(std::move(members));
    cones->push_back(cone);
  }
  return charts;
}

// The convex hull of `points`, counterclockwise (Andrew's monotone chain).
std::vector<glm::dvec2> convex_hull(std::vector<glm::dvec2> points) {
  std::sort(points.begin(), points.end(),
            [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  const auto turn = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<glm::dvec2> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {  // the lower chain, then the upper
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

// The direction of the long side of the least-area rectangle around `points`,
// which lies along an edge of their hull.
glm::dvec2 long_side(const std::vector<glm::dvec2>& points) {
  const std::vector<glm::dvec2> hull = convex_hull(points);
  glm::dvec2 best(1.0, 0.0);
  double least = INFINITY;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const glm::dvec2 edge = hull[(i + 1) % hull.size()] - hull[i];
    const double length = glm::length(edge);
    if (!(length > 0.0)) continue;
    const glm::dvec2 along = edge / length, across(-along.y, along.x);
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (const glm::dvec2& p : hull) {
      const glm::dvec2 q(glm::dot(p, along), glm::dot(p, across));
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
    const glm::dvec2 size = hi - lo;
    if (size.x * size.y < least) {
      least = size.x * size.y;
      best = size.x >= size.y ? along : across;
    }
  }
  return best;
}

// A chart's corners in its plane turned so that the least-area rectangle
// around them lies along their box, long side first (boxes then hold as
// little empty space as they can), and measured from the box's low corner.
FlatChart turned_flat(std::vector<glm::dvec2> corners) {
  const glm::dvec2 along = long_side(corners);
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  for (glm::dvec2& q : corners) {
    q = glm::dvec2(along.x * q.x + along.y * q.y, -along.y * q.x + along.x * q.y);  // a turn: no mirroring
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  for (glm::dvec2& q : corners) q -= lo;
  return FlatChart{std::move(corners), hi - lo};
}

}  // namespace

FlatChart projected_flat(const ChartSurface& surface, const std::vector<std::uint32_t>& members,
                         const glm::dvec3& axis) {
  glm::dvec3 u, v;
  plane_axes(axis, &u, &v);
  std::vector<glm::dvec2> corners;
  corners.reserve(3 * members.size());
  for (std::uint32_t i : members)
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3& p = surface.corners[3 * i + k];
      corners.emplace_back(glm::dot(p, u), glm::dot(p, v));
    }
  return turned_flat(std::move(corners));
}

FlatChart piece_flat(const std::vector<std::uint32_t>& members, const FlatChart& flat,
                     const std::vector<std::uint32_t>& piece) {
  std::unordered_map<std::uint32_t, std::size_t> position;
  for (std::size_t m = 0; m < members.size(); ++m) position.emplace(members[m], m);
  std::vector<glm::dvec2> corners;
  corners.reserve(3 * piece.size());
  for (std::uint32_t i : piece) {
    const std::size_t m = position.at(i);
    corners.insert(corners.end(), flat.corners.begin() + 3 * m, flat.corners.begin() + 3 * m + 3);
  }
  return turned_flat(std::move(corners));
}

namespace {

// The length of the edge that triangles i and j share.
double shared_edge_length(const ChartSurface& surface, std::uint32_t i, std::uint32_t j) {
  const std::uint32_t* of_j = &surface.corner_ids[3 * j];
  glm::dvec3 shared[3];
  int count = 0;
  for (int k = 0; k < 3; ++k)
    if (std::find(of_j, of_j + 3, surface.corner_ids[3 * i + k]) != of_j + 3)
      shared[count++] = surface.corners[3 * i + k];
  return count == 2 ? glm::distance(shared[0], shared[1]) : 0.0;
}

// Where a triangle shares a boundary longer by this factor with another
// piece, the cut gets shorter by more than the lengths' rounding.
constexpr double kLongerBoundary = 1.0 + 1e-9;

// The piece (other than its own, `piece_of[i]`) that triangle i shares the
// longest boundary with, where that is longer than the one it shares with its own.
std::optional<int> piece_sharing_more(const ChartSurface& surface, const std::vector<int>& piece_of, std::uint32_t i) {
  std::map<int, double> shared;
  for (std::uint32_t j : surface.neighbours[i])
    if (piece_of[j] >= 0) shared[piece_of[j]] += shared_edge_length(surface, i, j);
  const double own = shared[piece_of[i]];
  std::optional<int> best;
  for (const auto& [piece, length] : shared)
    if (length > kLongerBoundary * own && (!best || length > shared[*best])) best = piece;
  return best;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> shortened_cuts(const std::vector<std::vector<std::uint32_t>>& pieces,
                                                       const ChartSurface& surface) {
  std::vector<int> piece_of(surface.areas.size(), -1);
  std::vector<std::size_t> sizes;
  std::vector<std::uint32_t> members;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    for (std::uint32_t i : pieces[p]) piece_of[i] = int(p);
    sizes.push_back(pieces[p].size());
    members.insert(members.end(), pieces[p].begin(), pieces[p].end());
  }
  // Triangles to look at, first all in order, then the neighbours of each
  // that moved: a long cut may creep a triangle a move, and passes over all
  // of them would take as many passes.
  std::deque<std::uint32_t> waiting(members.begin(), members.end());
  std::vector<bool> is_waiting(surface.areas.size(), false);
  for (std::uint32_t i : members) is_waiting[i] = true;
  while (!waiting.empty()) {
    const std::uint32_t i = waiting.front();
    waiting.pop_front();
    is_waiting[i] = false;
    const int own = piece_of[i];
    const std::optional<int> other =
        sizes[std::size_t(own)] > 1 ? piece_sharing_more(surface, piece_of, i) : std::nullopt;
    if (!other) continue;
    --sizes[std::size_t(own)];
    ++sizes[std::size_t(*other)];
    piece_of[i] = *other;
    for (std::uint32_t j : surface.neighbours[i])
      if (piece_of[j] >= 0 && !is_waiting[j]) {
        is_waiting[j] = true;
        waiting.push_back(j);
      }
  }
  std::vector<std::vector<std::uint32_t>> shortened(pieces.size());
  for (std::uint32_t i : members) shortened[std::size_t(piece_of[i])].push_back(i);
  return shortened;
}

std::vector<std::vector<std::uint32_t>> connected_parts(const std::vector<std::vector<std::uint32_t>>& pieces,
                                                        const ChartSurface& surface) {
  std::vector<int> piece_of(surface.areas.size(), -1);
  for (std::size_t p = 0; p < pieces.size(); ++p)
    for (std::uint32_t i : pieces[p]) piece_of[i] = int(p);
  std::vector<std::vector<std::uint32_t>> parts;
  for (std::size_t p = 0; p < pieces.size(); ++p)
    for (std::uint32_t seed : pieces[p]) {
      if (piece_of[seed] != int(p)) continue;  // in a part already
      std::vector<std::uint32_t> part{seed};
      piece_of[seed] = -1;
      for (std::size_t next = 0; next < part.size(); ++next)
        for (std::uint32_t neighbour : surface.neighbours[part[next]])
          if (piece_of[neighbour] == int(p)) {
            piece_of[neighbour] = -1;
            part.push_back(neighbour);
          }
      parts.push_back(std::move(part));
    }
  return parts;
}

LaidCharts projected_charts(const ChartSurface& surface, const std::vector<int>& round) {
  LaidCharts grown;
  std::vector<Cone> cones;
  grown.members = grown_charts(surface, round, std::acos(kChartCosine), &cones);
  for (std::size_t c = 0; c < grown.members.size(); ++c) {
    const glm::dvec3 axis = glm::normalize(cones[c].axis);
    for (std::uint32_t i : grown.members[c])
      grown.worst_stretch = std::max(grown.worst_stretch, 1.0 / glm::dot(surface.normals[i], axis));
    grown.flat.push_back(projected_flat(surface, grown.members[c], axis));
    grown.axes.push_back(axis);
  }
  return grown;
}

namespace {

// Halves of a chart's triangles, cut at the median of their centroids along the axis they spread most along.
std::vector<std::vector<std::uint32_t>> halves(const ChartSurface& surface, const std::vector<std::uint32_t>& members) {
  std::vector<glm::dvec3> centroids;
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (std::uint32_t i : members) {
    centroids.push_back((surface.corners[3 * i] + surface.corners[3 * i + 1] + surface.corners[3 * i + 2]) / 3.0);
    lo = glm::min(lo, centroids.back());
    hi = glm::max(hi, centroids.back());
  }
  const glm::dvec3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  std::vector<std::size_t> order(members.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return centroids[a][axis] < centroids[b][axis]; });
  std::vector<std::vector<std::uint32_t>> two(2);
  for (std::size_t k = 0; k < order.size(); ++k) two[2 * k < order.size() ? 0 : 1].push_back(members[order[k]]);
  return two;
}

// A chart laid flat by a conformal map, or a triangle alone in its own plane.
struct ConformalPiece {
  std::vector<std::uint32_t> members;
  FlatChart flat;
  double stretch = 1.0;
};

// `members` laid flat by conformal_map within the stretch bound, if it can be.
std::optional<ConformalChart> conformal_map_of(const ChartSurface& surface, const std::vector<std::uint32_t>& members) {
  std::vector<glm::dvec3> corners;
  std::vector<std::uint32_t> ids;
  for (std::uint32_t i : members) {
    corners.insert(corners.end(), surface.corners.begin() + 3 * i, surface.corners.begin() + 3 * i + 3);
    ids.insert(ids.end(), surface.corner_ids.begin() + 3 * i, surface.corner_ids.begin() + 3 * i + 3);
  }
  return conformal_map(corners, ids, 1.0 / kChartCosine);
}

// Lays `members`, which join across edges, flat by a conformal map; where that
// stretches a triangle by more than 1 / kChartCosine (or turns one over) their
// halves' connected parts are laid flat instead, and so on. Triangles that
// overlap others of their chart in the map are taken out and laid flat the
// same way among themselves.
void lay_conformal(const ChartSurface& surface, const std::vector<std::uint32_t>& members,
                   std::vector<ConformalPiece>* pieces) {
  if (members.size() == 1) {  // in its own plane, without stretch, however thin it is
    pieces->push_back({members, projected_flat(surface, members, surface.normals[members[0]])});
    return;
  }
  const std::optional<ConformalChart> conformal = conformal_map_of(surface, members);
  if (!conformal) {
    for (const std::vector<std::uint32_t>& part :
         connected_parts(shortened_cuts(halves(surface, members), surface), surface))
      lay_conformal(surface, part, pieces);
    return;
  }
  std::vector<std::uint32_t> kept, overlapping;
  std::vector<glm::dvec2> kept_corners;
  for (std::size_t m = 0, next = 0; m < members.size(); ++m) {
    if (next < conformal->overlapping.size() && conformal->overlapping[next] == m) {
      ++next;
      overlapping.push_back(members[m]);
      continue;
    }
    kept.push_back(members[m]);
    kept_corners.insert(kept_corners.end(), conformal->corners.begin() + 3 * m, conformal->corners.begin() + 3 * m + 3);
  }
  pieces->push_back({std::move(kept), turned_flat(std::move(kept_corners)), conformal->stretch});
  for (const std::vector<std::uint32_t>& part : connected_parts({overlapping}, surface))
    lay_conformal(surface, part, pieces);
}

// The pieces beside piece p (by `piece_of` each triangle's, -1 for none) and
// the length of boundary p shares with each, the longest first.
std::vector<std::pair<std::size_t, double>> neighbours_by_boundary(const ChartSurface& surface,
                                                                   const std::vector<std::uint32_t>& members,
                                                                   const std::vector<std::ptrdiff_t>& piece_of,
                                                                   std::size_t p) {
  std::map<std::size_t, double> boundary;
  for (std::uint32_t i : members)
    for (std::uint32_t j : surface.neighbours[i])
      if (piece_of[j] >= 0 && std::size_t(piece_of[j]) != p)
        boundary[std::size_t(piece_of[j])] += shared_edge_length(surface, i, j);
  std::vector<std::pair<std::size_t, double>> longest(boundary.begin(), boundary.end());
  std::stable_sort(longest.begin(), longest.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  return longest;
}

// The length of the edges of p's triangles that no other triangle of p shares.
double perimeter(const ChartSurface& surface, const std::vector<std::uint32_t>& members,
                 const std::vector<std::ptrdiff_t>& piece_of, std::size_t p) {
  double length = 0.0;
  for (std::uint32_t i : members) {
    for (int k = 0; k < 3; ++k)
      length += glm::distance(surface.corners[3 * i + k], surface.corners[3 * i + (k + 1) % 3]);
    for (std::uint32_t j : surface.neighbours[i])
      if (piece_of[j] == std::ptrdiff_t(p)) length -= shared_edge_length(surface, i, j);
  }
  return length;
}

// Pieces merged two at a time while a conformal map lays the two flat as one
// within the stretch bound, turning none over and overlapping none (after
// Sander et al. 2001's chart merging): each merge takes a seam, and the
// padding along it, out of the texture. The smallest piece goes first, into
// the neighbour it shares the longest boundary with that it can join. A merge
// must also leave the chart no less compact (perimeter squared over area, on
// the surface) than the geometric mean of the two's: taking every merge the
// map allows left ragged outlines that packed worse on a smooth model (the
// bunny), and a stricter bound (no less compact than the more compact of the
// two) kept too many of a hard-surface model's (the helmet's) pieces apart.
class PieceMerger {
 public:
  PieceMerger(const ChartSurface& surface, std::vector<ConformalPiece> pieces)
      : surface_(surface), pieces_(std::move(pieces)), piece_of_(surface.areas.size(), -1) {
    for (std::size_t p = 0; p < pieces_.size(); ++p)
      for (std::uint32_t i : pieces_[p].members) piece_of_[i] = std::ptrdiff_t(p);
    for (std::size_t p = 0; p < pieces_.size(); ++p) {
      area_.push_back(0.0);
      for (std::uint32_t i : pieces_[p].members) area_[p] += surface.areas[i];
      perimeter_.push_back(perimeter(surface, pieces_[p].members, piece_of_, p));
    }
    alive_.assign(pieces_.size(), true);
  }

  std::vector<ConformalPiece> merged() && {
    while (merge_pass()) {
    }
    std::vector<ConformalPiece> kept;
    for (std::size_t p = 0; p < pieces_.size(); ++p)
      if (alive_[p]) kept.push_back(std::move(pieces_[p]));
    return kept;
  }

 private:
  // Each piece, smallest first, merged into a neighbour where it can be; whether any was.
  bool merge_pass() {
    std::vector<std::size_t> smallest_first;
    for (std::size_t p = 0; p < pieces_.size(); ++p)
      if (alive_[p]) smallest_first.push_back(p);
    std::stable_sort(smallest_first.begin(), smallest_first.end(),
                     [&](std::size_t a, std::size_t b) { return area_[a] < area_[b]; });
    bool any = false;
    for (std::size_t p : smallest_first)
      if (alive_[p])  // not merged earlier in the pass
        for (const auto& [q, shared] : neighbours_by_boundary(surface_, pieces_[p].members, piece_of_, p))
          if (try_merge(p, q, shared)) {
            any = true;
            break;
          }
    return any;
  }

  static double compactness(double perimeter, double area) { return perimeter * perimeter / area; }

  bool try_merge(std::size_t p, std::size_t q, double shared) {
    const std::pair<std::size_t, std::size_t> pair(std::min(p, q), std::max(p, q));
    if (refused_.count(pair)) return false;
    const double perimeter = perimeter_[p] + perimeter_[q] - 2.0 * shared, area = area_[p] + area_[q];
    if (compactness(perimeter, area) <=
        std::sqrt(compactness(perimeter_[p], area_[p]) * compactness(perimeter_[q], area_[q]))) {
      std::vector<std::uint32_t> both = pieces_[p].members;
      both.insert(both.end(), pieces_[q].members.begin(), pieces_[q].members.end());
      const std::optional<ConformalChart> conformal = conformal_map_of(surface_, both);
      if (conformal && conformal->overlapping.empty()) {
        replace(p, q, {std::move(both), turned_flat(conformal->corners), conformal->stretch}, area, perimeter);
        return true;
      }
    }
    refused_.insert(pair);
    return false;
  }

  void replace(std::size_t p, std::size_t q, ConformalPiece both, double area, double perimeter) {
    for (std::uint32_t i : both.members) piece_of_[i] = std::ptrdiff_t(pieces_.size());
    pieces_[p] = pieces_[q] = ConformalPiece{};
    alive_[p] = alive_[q] = false;
    pieces_.push_back(std::move(both));
    area_.push_back(area);
    perimeter_.push_back(perimeter);
    alive_.push_back(true);
  }

  const ChartSurface& surface_;
  std::vector<ConformalPiece> pieces_;  // those merged away left empty
  std::vector<std::ptrdiff_t> piece_of_;
  std::vector<double> area_, perimeter_;
  std::vector<bool> alive_;
  std::set<std::pair<std::size_t, std::size_t>> refused_;  // pairs that cannot merge, as they are
};

}  // namespace

LaidCharts conformal_charts(const ChartSurface& surface, const std::vector<int>& round) {
  std::vector<ConformalPiece> pieces;
  std::vector<Cone> cones;  // any cone: the parts that join across edges
  for (const std::vector<std::uint32_t>& part : grown_charts(surface, round, M_PI, &cones))
    lay_conformal(surface, part, &pieces);
  LaidCharts laid;
  for (ConformalPiece& piece : PieceMerger(surface, std::move(pieces)).merged()) {
    laid.members.push_back(std::move(piece.members));
    laid.flat.push_back(std::move(piece.flat));
    laid.axes.emplace_back();
    laid.worst_stretch = std::max(laid.worst_stretch, piece.stretch);
  }
  return laid;
}

}  // namespace mbao
