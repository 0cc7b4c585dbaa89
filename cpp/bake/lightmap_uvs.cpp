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

#include "bake/chart_packing.h"
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

// A round's charts: each one's triangles (local indices), and those laid flat in its plane, in their order.
struct Charts {
  std::vector<std::vector<std::uint32_t>> members;
  std::vector<FlatChart> flat;
};

// An orthonormal basis of the plane perpendicular to unit n (Duff et al. 2017).
void plane_axes(const glm::dvec3& n, glm::dvec3* u, glm::dvec3* v) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  *u = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
  *v = {b, sign + n.y * n.y * a, -n.y};
}

// The triangles asked for: their unit normals, areas, neighbours and corners.
struct Surface {
  std::vector<glm::dvec3> normals;
  std::vector<double> areas;
  std::vector<std::vector<std::uint32_t>> neighbours;  // local indices, across edges between equal positions
  std::vector<glm::dvec3> corners;                     // three per triangle
  std::vector<std::uint32_t> corner_ids;               // equal where corners' positions are
};

Surface surface_of(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles) {
  const std::size_t n = triangles.size();
  Surface s;
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
std::vector<std::vector<std::uint32_t>> grown_charts(const Surface& surface, const std::vector<int>& round,
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

// `members` projected onto the plane perpendicular to unit `axis`, turned.
FlatChart projected_flat(const Surface& surface, const std::vector<std::uint32_t>& members, const glm::dvec3& axis) {
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

// The corners of `piece`, some of a chart's `members`, from its `flat`, turned anew.
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

double box_area(const FlatChart& chart) { return chart.size.x * chart.size.y; }

// The density at which the charts' boxes' area alone would fill the texture; 1 where they have none.
double filling_density(const std::vector<FlatChart>& charts, int width, int height) {
  double boxes = 0.0;
  for (const FlatChart& chart : charts) boxes += box_area(chart);
  return boxes > 0.0 ? std::sqrt(double(width) * double(height) / boxes) : 1.0;
}

// A chart's triangles cut across its long side (its box's x) into `pieces`
// of equal length, each triangle going with its centroid.
std::vector<std::vector<std::uint32_t>> cut_across(const std::vector<std::uint32_t>& members, const FlatChart& flat,
                                                   std::size_t pieces) {
  std::vector<std::vector<std::uint32_t>> cut(pieces);
  for (std::size_t m = 0; m < members.size(); ++m) {
    const double centroid = (flat.corners[3 * m].x + flat.corners[3 * m + 1].x + flat.corners[3 * m + 2].x) / 3.0;
    const auto piece = std::size_t(std::clamp(centroid / flat.size.x * double(pieces), 0.0, double(pieces - 1)));
    cut[piece].push_back(members[m]);
  }
  cut.erase(std::remove_if(cut.begin(), cut.end(), [](const auto& piece) { return piece.empty(); }), cut.end());
  return cut;
}

// Where a chart is cut across its length (SPEC 6.3), in shares of the
// texture's shorter side at the density at which the charts' boxes would fill
// the texture, or in texels per texel of padding:
constexpr double kStripShare = 0.25;      // a strip more than twice as long as wide; also the pieces' length
constexpr double kHollowPaddings = 16.0;  // a chart whose triangles fill less than kHollowFill of its box
constexpr double kHollowFill = 0.6;
constexpr double kLargeShare = 0.375;  // any chart, where that packs better

// Those lengths in world units.
struct CutLengths {
  double strip = 0.0, hollow = 0.0, large = 0.0;
};

// The area of a chart's triangles.
double triangles_area(const FlatChart& chart) {
  double sum = 0.0;
  for (std::size_t i = 0; i + 2 < chart.corners.size(); i += 3) {
    const glm::dvec2 a = chart.corners[i + 1] - chart.corners[i], b = chart.corners[i + 2] - chart.corners[i];
    sum += 0.5 * std::abs(a.x * b.y - a.y * b.x);
  }
  return sum;
}

// Whether a chart packs better cut across its length: a long strip (a
// moulding, a rim) would set the density for every chart, and a hollow one (a
// rose window, a column's capital) holds its box's middle empty, where it is
// long against the padding that cutting adds. A large one (a room's wall) is
// cut where `cut_large`: a few of them tile a square badly, but one alone
// tiles it well.
bool worth_cutting(const FlatChart& flat, const CutLengths& lengths, bool cut_large) {
  const double length = flat.size.x;
  return (length > lengths.strip && length > 2.0 * flat.size.y) ||
         (length > lengths.hollow && triangles_area(flat) < kHollowFill * box_area(flat)) ||
         (cut_large && length > lengths.large);
}

// Each piece split where its triangles do not join across edges: a ring cut
// across leaves two arcs in a piece.
std::vector<std::vector<std::uint32_t>> connected_parts(const std::vector<std::vector<std::uint32_t>>& pieces,
                                                        const Surface& surface) {
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

// The charts of a round as grown, each laid flat.
struct GrownCharts {
  std::vector<std::vector<std::uint32_t>> members;
  std::vector<FlatChart> flat;
  std::vector<std::optional<glm::dvec3>> axes;  // a projected chart's; none where a conformal map laid it flat
  double worst_stretch = 1.0;  // the largest factor by which a chart lengthens or shortens a direction in a triangle
  CutLengths cut_lengths;
};

// The lengths at which the charts are cut, from the texel at which their boxes would fill the texture.
void set_cut_lengths(GrownCharts* grown, int width, int height, int padding) {
  const double texel = 1.0 / filling_density(grown->flat, width, height), side = std::min(width, height) * texel;
  grown->cut_lengths = {kStripShare * side, kHollowPaddings * std::max(padding, 1) * texel, kLargeShare * side};
}

// Charts grown within a cone of half-angle acos(kChartCosine), each projected
// onto the plane perpendicular to its axis: no triangle's area shrinks by more
// than 1 / kChartCosine.
GrownCharts projected_charts(const Surface& surface, const std::vector<int>& round, int width, int height,
                             int padding) {
  GrownCharts grown;
  std::vector<Cone> cones;
  grown.members = grown_charts(surface, round, std::acos(kChartCosine), &cones);
  for (std::size_t c = 0; c < grown.members.size(); ++c) {
    const glm::dvec3 axis = glm::normalize(cones[c].axis);
    for (std::uint32_t i : grown.members[c])
      grown.worst_stretch = std::max(grown.worst_stretch, 1.0 / glm::dot(surface.normals[i], axis));
    grown.flat.push_back(projected_flat(surface, grown.members[c], axis));
    grown.axes.push_back(axis);
  }
  set_cut_lengths(&grown, width, height, padding);
  return grown;
}

// Halves of a chart's triangles, cut at the median of their centroids along the axis they spread most along.
std::vector<std::vector<std::uint32_t>> halves(const Surface& surface, const std::vector<std::uint32_t>& members) {
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

// Lays `members`, which join across edges, flat by a conformal map; where that
// stretches a triangle by more than 1 / kChartCosine (or turns one over) their
// halves' connected parts are laid flat instead, and so on. Triangles that
// overlap others of their chart in the map are taken out and laid flat the
// same way among themselves.
void lay_conformal(const Surface& surface, const std::vector<std::uint32_t>& members, GrownCharts* grown) {
  if (members.size() == 1) {  // in its own plane, without stretch, however thin it is
    grown->flat.push_back(projected_flat(surface, members, surface.normals[members[0]]));
    grown->members.push_back(members);
    grown->axes.emplace_back();
    return;
  }
  std::vector<glm::dvec3> corners;
  std::vector<std::uint32_t> ids;
  for (std::uint32_t i : members) {
    corners.insert(corners.end(), surface.corners.begin() + 3 * i, surface.corners.begin() + 3 * i + 3);
    ids.insert(ids.end(), surface.corner_ids.begin() + 3 * i, surface.corner_ids.begin() + 3 * i + 3);
  }
  std::optional<ConformalChart> conformal = conformal_map(corners, ids, 1.0 / kChartCosine);
  if (!conformal) {
    for (const std::vector<std::uint32_t>& part : connected_parts(halves(surface, members), surface))
      lay_conformal(surface, part, grown);
    return;
  }
  grown->worst_stretch = std::max(grown->worst_stretch, conformal->stretch);
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
  grown->flat.push_back(turned_flat(std::move(kept_corners)));
  grown->members.push_back(std::move(kept));
  grown->axes.emplace_back();
  for (const std::vector<std::uint32_t>& part : connected_parts({overlapping}, surface))
    lay_conformal(surface, part, grown);
}

// Each connected part of the round's triangles laid flat by conformal maps, cut in halves where they stretch.
GrownCharts conformal_charts(const Surface& surface, const std::vector<int>& round, int width, int height,
                             int padding) {
  GrownCharts grown;
  std::vector<Cone> cones;  // any cone: the parts that join across edges
  for (const std::vector<std::uint32_t>& part : grown_charts(surface, round, M_PI, &cones))
    lay_conformal(surface, part, &grown);
  set_cut_lengths(&grown, width, height, padding);
  return grown;
}

// A chart's triangles and how they lie flat, as charts: while worth cutting,
// cut across into pieces no longer than a strip may be (two at least) and
// those into connected parts, each projected anew along a projected chart's
// axis (it may turn), or where the chart's conformal map laid it, turned anew.
class Cutter {
 public:
  Cutter(const Surface& surface, const CutLengths& lengths, bool cut_large)
      : surface_(surface), lengths_(lengths), cut_large_(cut_large) {}

  void add(std::vector<std::uint32_t> members, FlatChart flat, const std::optional<glm::dvec3>& axis,
           Charts* charts) const {
    std::vector<std::vector<std::uint32_t>> pieces;
    if (worth_cutting(flat, lengths_, cut_large_)) {
      const auto count = std::max<std::size_t>(2, std::size_t(std::ceil(flat.size.x / lengths_.strip)));
      pieces = connected_parts(cut_across(members, flat, count), surface_);
    }
    if (pieces.size() < 2) {  // not worth it, or one triangle spans its length
      charts->members.push_back(std::move(members));
      charts->flat.push_back(std::move(flat));
      return;
    }
    for (std::vector<std::uint32_t>& piece : pieces) {
      FlatChart laid = axis ? projected_flat(surface_, piece, *axis) : piece_flat(members, flat, piece);
      add(std::move(piece), std::move(laid), axis, charts);
    }
  }

 private:
  const Surface& surface_;
  CutLengths lengths_;
  bool cut_large_;
};

Charts cut_charts(const Surface& surface, const GrownCharts& grown, bool cut_large) {
  const Cutter cutter(surface, grown.cut_lengths, cut_large);
  Charts charts;
  for (std::size_t c = 0; c < grown.members.size(); ++c)
    cutter.add(grown.members[c], grown.flat[c], grown.axes[c], &charts);
  return charts;
}

bool has_large(const Charts& charts, const CutLengths& lengths) {
  return std::any_of(charts.flat.begin(), charts.flat.end(),
                     [&](const FlatChart& flat) { return flat.size.x > lengths.large; });
}

// Charts by their boxes' area, largest first, so that small ones fill the gaps large ones leave.
std::vector<std::size_t> largest_first(const std::vector<FlatChart>& charts) {
  std::vector<std::size_t> order(charts.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return box_area(charts[a]) > box_area(charts[b]); });
  return order;
}

// The least density tried: charts of more than 1e-270 world units still get boxes of 2 texels.
constexpr double kLeastDensity = 1e-30;

// Whether the charts fit at some density above 0, `padding` apart: each a
// texel in a box of 2 x 2 (1 x 1 where it has no extent). At density 0 itself
// every chart would shrink to a point, which covers no texel.
bool fit_at_all(const std::vector<FlatChart>& charts, int width, int height, int padding) {
  return packed_charts(charts, largest_first(charts), kLeastDensity, width, height, padding).has_value();
}

// The largest padding up to `padding` at which the charts fit at all, if any.
std::optional<int> fitting_padding(const std::vector<FlatChart>& charts, int width, int height, int padding) {
  for (int p = padding; p >= 0; --p)
    if (fit_at_all(charts, width, height, p)) return p;
  return std::nullopt;
}

// The texture size, `width` x `height` times the least power of two, at which
// the charts fit `padding` apart; none up to kMaxTextureSide.
std::optional<glm::ivec2> size_keeping(const std::vector<FlatChart>& charts, int width, int height, int padding) {
  for (long long w = width, h = height; std::max(w, h) <= kMaxTextureSide; w *= 2, h *= 2)
    if (fit_at_all(charts, int(w), int(h), padding)) return glm::ivec2(int(w), int(h));
  return std::nullopt;
}

// Steps of the density's bisection once it is within a factor 2: the last
// changes it by less than 0.1%.
constexpr int kDensitySteps = 10;

// The largest density at which the charts fit `padding` apart (they must fit
// at kLeastDensity), and where each goes: halving from twice the one at which
// their boxes' area alone would fill the texture until they fit, then by
// bisection in ratio.
double densest_packing(const std::vector<FlatChart>& charts, int width, int height, int padding,
                       std::vector<Placement>* placed) {
  const std::vector<std::size_t> order = largest_first(charts);
  double hi = 2.0 * filling_density(charts, width, height), lo = 0.5 * hi;
  std::optional<std::vector<Placement>> fits;
  for (; lo > kLeastDensity && !(fits = packed_charts(charts, order, lo, width, height, padding)); lo *= 0.5) hi = lo;
  if (!fits) {
    lo = kLeastDensity;
    fits = packed_charts(charts, order, lo, width, height, padding);
  }
  *placed = std::move(*fits);
  for (int step = 0; step < kDensitySteps; ++step) {
    const double middle = std::sqrt(lo * hi);
    if ((fits = packed_charts(charts, order, middle, width, height, padding))) {
      lo = middle;
      *placed = std::move(*fits);
    } else {
      hi = middle;
    }
  }
  return lo;
}

std::vector<glm::vec2> chart_uvs(const Charts& charts, const std::vector<Placement>& placed, double density,
                                 std::size_t triangles, int width, int height) {
  std::vector<glm::vec2> uvs(3 * triangles, glm::vec2(0.0f));
  for (std::size_t c = 0; c < charts.members.size(); ++c) {
    // Half a texel in from the box's corner: the box is a texel larger than the chart.
    const glm::dvec2 origin = glm::dvec2(placed[c].corner) + 0.5;
    const FlatChart flat = placed[c].half_turned ? half_turned(charts.flat[c]) : charts.flat[c];
    for (std::size_t m = 0; m < charts.members[c].size(); ++m)
      for (std::size_t k = 0; k < 3; ++k) {
        const glm::dvec2 q = flat.corners[3 * m + k] * density + origin;
        uvs[3 * std::size_t(charts.members[c][m]) + k] = glm::vec2(q.x / width, q.y / height);
      }
  }
  return uvs;
}

// Charts packed into the texture at the largest padding up to the one asked for, and then the largest density.
struct Packing {
  Charts charts;
  int padding = 0;
  std::optional<glm::ivec2> size_keeping_padding;
  double density = 0.0;
  std::vector<Placement> placed;
  double worst_stretch = 1.0;  // the charts' (GrownCharts)
};

std::optional<Packing> packing(Charts charts, int width, int height, int padding) {
  const std::optional<int> fitting = fitting_padding(charts.flat, width, height, padding);
  if (!fitting) return std::nullopt;
  Packing packing;
  packing.padding = *fitting;
  if (packing.padding < padding) packing.size_keeping_padding = size_keeping(charts.flat, width, height, padding);
  packing.density = densest_packing(charts.flat, width, height, packing.padding, &packing.placed);
  packing.charts = std::move(charts);
  return packing;
}

// The texels a packing's triangles cover, near enough: their area in the texture.
double texel_area(const Packing& packing) {
  double area = 0.0;
  for (const FlatChart& chart : packing.charts.flat) area += triangles_area(chart);
  return area * packing.density * packing.density;
}

// Whichever of two packings fits at the larger padding, then covers more
// texels (charts laid flat differently differ in area at one density); `a`
// where they tie.
std::optional<Packing> better_of(std::optional<Packing> a, std::optional<Packing> b) {
  if (!a || !b) return a ? std::move(a) : std::move(b);
  const bool b_better = b->padding > a->padding || (b->padding == a->padding && texel_area(*b) > texel_area(*a));
  return b_better ? std::move(b) : std::move(a);
}

// The round's charts packed, with large charts cut or not, whichever packs better.
std::optional<Packing> best_packing(const Surface& surface, const GrownCharts& grown, int width, int height,
                                    int padding) {
  Charts whole = cut_charts(surface, grown, false);
  const bool large = has_large(whole, grown.cut_lengths);
  std::optional<Packing> packed = packing(std::move(whole), width, height, padding);
  if (large) packed = better_of(std::move(packed), packing(cut_charts(surface, grown, true), width, height, padding));
  if (packed) packed->worst_stretch = grown.worst_stretch;
  return packed;
}

// The round's charts grown in cones and projected, or laid flat by conformal
// maps, whichever packs better (the projected where they tie).
Packing round_packing(const Surface& surface, const std::vector<int>& round, int width, int height, int padding) {
  const GrownCharts projected = projected_charts(surface, round, width, height, padding);
  std::optional<Packing> packed = better_of(
      best_packing(surface, projected, width, height, padding),
      best_packing(surface, conformal_charts(surface, round, width, height, padding), width, height, padding));
  if (!packed)
    throw std::invalid_argument("generated UVs: " + std::to_string(projected.members.size()) + " charts do not fit " +
                                std::to_string(width) + " x " + std::to_string(height) +
                                " texels even at a texel each and touching; raise the resolution");
  return std::move(*packed);
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
    const Packing packed = round_packing(surface, round, width, height, padding);
    result.worst_stretch = packed.worst_stretch;
    result.padding = packed.padding;
    result.size_keeping_padding = packed.size_keeping_padding;
    result.texels_per_unit = packed.density;
    result.charts = packed.charts.flat.size();
    result.corner_uvs = chart_uvs(packed.charts, packed.placed, packed.density, triangles.size(), width, height);
    result.layout.emplace(mesh, triangles, result.corner_uvs, width, height, WrapMode::Repeat, WrapMode::Repeat);
    if (result.layout->second_claimants().empty()) return result;
    for (std::size_t i : result.layout->second_claimants()) round[i] = r + 1;
  }
  throw std::logic_error("generated UVs: charts still overlap after " + std::to_string(kMaxRounds) + " rounds");
}

}  // namespace mbao
