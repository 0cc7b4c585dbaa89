#include "bake/texel_layout.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace mbao {
namespace {

// A convex polygon of at most 3 + 4 corners: a triangle clipped to a box.
struct Polygon {
  glm::dvec2 p[8];
  int n = 0;
};

// The part of `in` where axis coordinate `axis` is >= bound (keep_above) or <= bound.
Polygon clip(const Polygon& in, int axis, double bound, bool keep_above) {
  Polygon out;
  for (int i = 0; i < in.n; ++i) {
    const glm::dvec2 a = in.p[i], b = in.p[(i + 1) % in.n];
    const double da = keep_above ? a[axis] - bound : bound - a[axis];
    const double db = keep_above ? b[axis] - bound : bound - b[axis];
    if (da >= 0.0) out.p[out.n++] = a;
    if ((da < 0.0) != (db < 0.0)) {
      glm::dvec2 c = a + (b - a) * (da / (da - db));
      c[axis] = bound;  // exactly on the boundary, whatever the rounding
      out.p[out.n++] = c;
    }
  }
  return out;
}

Polygon clip_to_cell(const Polygon& in, double x, double y) {
  return clip(clip(clip(clip(in, 0, x, true), 0, x + 1.0, false), 1, y, true), 1, y + 1.0, false);
}

double area(const Polygon& poly) {
  double twice = 0.0;
  for (int i = 0; i < poly.n; ++i) {
    const glm::dvec2 a = poly.p[i], b = poly.p[(i + 1) % poly.n];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * std::abs(twice);
}

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// The edge between a and b from its endpoints in one fixed order, whichever
// triangle names it: its lower end and its way to the other.
struct OrderedEdge {
  glm::dvec2 lo, d;
};

OrderedEdge ordered_edge(glm::dvec2 a, glm::dvec2 b) {
  const bool in_order = a.x < b.x || (a.x == b.x && a.y < b.y);
  const glm::dvec2 lo = in_order ? a : b;
  return {lo, (in_order ? b : a) - lo};
}

// The side of the edge between a and b that p is on, computed from the
// ordered edge, so that two triangles sharing the edge get the same number
// with opposite meanings (SPEC 6.3's fill rule).
double edge_side(glm::dvec2 a, glm::dvec2 b, glm::dvec2 p) {
  const OrderedEdge e = ordered_edge(a, b);
  return cross(e.d, p - e.lo);
}

// The 4 x 4 sample points of a texel, offset by d = 1/1000 so that they are not dyadic like most UVs.
constexpr int kClaimPoints = 4;
double claim_offset(int i) { return (i + 0.5 + 1e-3) / kClaimPoints; }
constexpr std::uint16_t kAllClaimPoints = 0xffff;

// Per edge k of a triangle (corners k, k + 1): edge_side of the third
// corner, whose sign is that of the triangle's side. Returns false where one
// is 0: the triangle is too thin for edge_side to tell its sides.
bool inside_signs(const std::array<glm::dvec2, 3>& c, double sign[3]) {
  for (int k = 0; k < 3; ++k)
    sign[k] = edge_side(c[std::size_t(k)], c[std::size_t((k + 1) % 3)], c[std::size_t((k + 2) % 3)]);
  return sign[0] != 0.0 && sign[1] != 0.0 && sign[2] != 0.0;
}

// Where a cell of the UV plane lies against a triangle: inside it, or
// outside one of its edges, by far more than edge_side's rounding (a few ulps
// of its two products) at all four corners, and so, edge_side being linear,
// at every point between them; else across its boundary. A cell inside is
// the triangle's piece whole, of area 1, and holds all its sample points; one
// outside holds nothing; in one across, a point lies on the triangle's side
// of every edge whose line does not cross the cell. These are the answers of
// clipping and of testing 16 points, at a fraction of their cost, for most
// cells of a triangle's box.
struct CellPlace {
  bool outside = false;       // wholly outside an edge
  unsigned edges_across = 0;  // bit k: edge k's line may cross the cell
  bool inside() const { return !outside && edges_across == 0; }
};

class CellPlaces {
 public:
  // sign: inside_signs of the triangle c. An edge of sign 0 crosses every cell.
  CellPlaces(const std::array<glm::dvec2, 3>& c, const double sign[3]) {
    for (std::size_t k = 0; k < 3; ++k) {
      Edge& e = edges_[k];
      e.line = ordered_edge(c[k], c[(k + 1) % 3]);  // as edge_side orders it
      const glm::dvec2 d = e.line.d;
      e.toward_inside = sign[k] > 0.0 ? 1.0 : (sign[k] < 0.0 ? -1.0 : 0.0);
      // From corner (x, y) to (x + 1, y), (x, y + 1) and (x + 1, y + 1), edge_side changes by -d.y, d.x and both.
      const double steps[4] = {0.0, -d.y, d.x, d.x - d.y};
      e.least = e.most = 0.0;
      for (const double step : steps) {
        e.least = std::min(e.least, e.toward_inside * step);
        e.most = std::max(e.most, e.toward_inside * step);
      }
    }
  }

  // Cell (x, y): [x, x + 1] x [y, y + 1].
  CellPlace operator()(double x, double y) const {
    constexpr double kMargin = 1e-9;  // relative to the products' size; rounding is ~1e-16 of it
    CellPlace place;
    for (unsigned k = 0; k < 3; ++k) {
      const Edge& e = edges_[k];
      const glm::dvec2 d = e.line.d, from = glm::dvec2(x, y) - e.line.lo;
      const double side = e.toward_inside * cross(d, from);
      const double margin =
          kMargin * (std::abs(d.x) * (std::abs(from.y) + 1.0) + std::abs(d.y) * (std::abs(from.x) + 1.0));
      if (side + e.most < -margin) return {true, 0};
      if (!(side + e.least > margin)) place.edges_across |= 1u << k;
    }
    return place;
  }

 private:
  struct Edge {
    OrderedEdge line;
    double toward_inside;  // +1 or -1: the sign of edge_side on the triangle's side (0: unknown)
    double least, most;    // the least and most change toward the inside from corner (x, y) to the others
  };
  std::array<Edge, 3> edges_;
};

}  // namespace

TexelLayout::TexelLayout(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                         const std::vector<glm::vec2>& corner_uvs, int width, int height, WrapMode wrap_s,
                         WrapMode wrap_t)
    : width_(width), height_(height), wrap_s_(wrap_s), wrap_t_(wrap_t) {
  if (width < 1 || height < 1 || width > kMaxTextureSide || height > kMaxTextureSide)
    throw std::invalid_argument("resolution must be in [1, " + std::to_string(kMaxTextureSide) +
                                "] on each side, got " + std::to_string(width) + " x " + std::to_string(height));
  if (corner_uvs.size() != 3 * triangles.size())
    throw std::invalid_argument("texcoords: " + std::to_string(corner_uvs.size()) + " corners' UVs for " +
                                std::to_string(triangles.size()) + " triangles");
  std::vector<double> surface_per_texel;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const std::uint32_t t = triangles[i];
    if (t >= mesh.triangles.size()) throw std::invalid_argument("triangle " + std::to_string(t) + " does not exist");
    const glm::uvec3 v = mesh.triangles[t];
    Corners c;
    for (int k = 0; k < 3; ++k) {
      const glm::vec2 uv = corner_uvs[3 * i + std::size_t(k)];
      if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
        throw std::invalid_argument("texcoords: corner " + std::to_string(k) + " (vertex " + std::to_string(v[k]) +
                                    ") of triangle " + std::to_string(t) + " has no finite UV");
      c[std::size_t(k)] = {double(uv.x) * width, double(uv.y) * height};
    }
    const double uv_area = 0.5 * std::abs(cross(c[1] - c[0], c[2] - c[0]));
    if (!(uv_area > 0.0)) {
      ++unmapped_;
      continue;
    }
    const glm::dvec3 p0(mesh.positions[v.x]), p1(mesh.positions[v.y]), p2(mesh.positions[v.z]);
    triangles_.push_back(t);
    given_at_.push_back(i);
    corners_.push_back(c);
    surface_per_texel.push_back(0.5 * glm::length(glm::cross(p1 - p0, p2 - p0)) / uv_area);
  }

  std::vector<TexelPiece> pieces;
  for (std::uint32_t i = 0; i < triangles_.size(); ++i) add_pieces(i, surface_per_texel[i], pieces);
  const std::size_t texels = std::size_t(width) * std::size_t(height);
  piece_start_.assign(texels + 1, 0);
  for (const TexelPiece& p : pieces) ++piece_start_[p.texel + 1];
  for (std::size_t i = 0; i < texels; ++i) piece_start_[i + 1] += piece_start_[i];
  pieces_.resize(pieces.size());
  std::vector<std::size_t> next(piece_start_.begin(), piece_start_.end() - 1);
  for (const TexelPiece& p : pieces) pieces_[next[p.texel]++] = p.piece;  // in triangle order within a texel
  covered_.assign(texels, 0);
  for (std::size_t i = 0; i < texels; ++i) {
    double sum = 0.0;
    for (std::size_t k = piece_start_[i]; k < piece_start_[i + 1]; ++k) sum = pieces_[k].area_so_far += sum;
    covered_[i] = sum > 0.0;
    covered_count_ += covered_[i];
  }

  std::vector<std::uint16_t> once(texels, 0), twice(texels, 0);
  for (std::uint32_t i = 0; i < triangles_.size(); ++i)
    if (count_claims(i, once, twice)) second_claimants_.push_back(given_at_[i]);
  for (std::size_t i = 0; i < texels; ++i) claimed_twice_ += covered_[i] && twice[i] != 0;
}

std::int64_t TexelLayout::texel_along(std::int64_t cell, int n, WrapMode wrap, bool clamp_beyond,
                                      bool* mirrored) const {
  *mirrored = false;
  const std::int64_t period = cell >= 0 ? cell / n : -((-cell - 1) / n) - 1;  // floor(cell / n)
  const std::int64_t in_period = cell - period * n;
  switch (wrap) {
    case WrapMode::Repeat: return in_period;
    case WrapMode::MirroredRepeat: *mirrored = (period & 1) != 0; return *mirrored ? n - 1 - in_period : in_period;
    case WrapMode::ClampToEdge:
      if (period != 0 && clamp_beyond) return -1;
      return std::clamp<std::int64_t>(cell, 0, n - 1);
  }
  return -1;
}

void TexelLayout::add_pieces(std::uint32_t local, double surface_per_texel, std::vector<TexelPiece>& pieces) const {
  const Corners& c = corners_[local];
  Polygon triangle;
  triangle.n = 3;
  std::copy(c.begin(), c.end(), triangle.p);
  const glm::dvec2 lo = glm::min(glm::min(c[0], c[1]), c[2]), hi = glm::max(glm::max(c[0], c[1]), c[2]);
  const double cells = (std::floor(hi.x) - std::floor(lo.x) + 1.0) * (std::floor(hi.y) - std::floor(lo.y) + 1.0);
  if (cells + double(pieces.size()) > double(kMaxPieces))
    throw std::invalid_argument("texcoords: the UVs of triangle " + std::to_string(triangles_[local]) + " span " +
                                std::to_string(cells) + " texels; a layout holds at most " +
                                std::to_string(kMaxPieces) + " pieces (are the UVs in the range [0, 1]?)");
  double sign[3];
  inside_signs(c, sign);
  const CellPlaces places(c, sign);
  for (double y = std::floor(lo.y); y <= hi.y; y += 1.0) {
    const Polygon row = clip(clip(triangle, 1, y, true), 1, y + 1.0, false);
    for (double x = std::floor(lo.x); x <= hi.x; x += 1.0) {
      const CellPlace place = places(x, y);
      if (place.outside) continue;
      const double a = place.inside() ? 1.0 : area(clip(clip(row, 0, x, true), 0, x + 1.0, false));
      if (!(a > 0.0)) continue;
      bool mirrored;
      const std::int64_t tx = texel_along(std::int64_t(x), width_, wrap_s_, false, &mirrored);
      const std::int64_t ty = texel_along(std::int64_t(y), height_, wrap_t_, false, &mirrored);
      pieces.push_back(
          {std::uint32_t(ty * width_ + tx), {local, std::int32_t(x), std::int32_t(y), a * surface_per_texel}});
    }
  }
}

bool TexelLayout::count_claims(std::uint32_t local, std::vector<std::uint16_t>& once,
                               std::vector<std::uint16_t>& twice) const {
  const Corners& c = corners_[local];
  double inside_sign[3];
  if (!inside_signs(c, inside_sign)) return false;  // too thin to hold a point
  const CellPlaces places(c, inside_sign);
  const auto inside = [&](glm::dvec2 p, unsigned edges) {
    for (int k = 0; k < 3; ++k) {
      if (!(edges & (1u << k))) continue;
      const double side = edge_side(c[std::size_t(k)], c[std::size_t((k + 1) % 3)], p);
      if (side == 0.0 ? inside_sign[k] < 0.0 : (side > 0.0) != (inside_sign[k] > 0.0)) return false;
    }
    return true;
  };
  const glm::dvec2 lo = glm::min(glm::min(c[0], c[1]), c[2]), hi = glm::max(glm::max(c[0], c[1]), c[2]);
  bool again = false;
  for (double y = std::floor(lo.y); y <= hi.y; y += 1.0) {
    bool mirrored_y;
    const std::int64_t ty = texel_along(std::int64_t(y), height_, wrap_t_, true, &mirrored_y);
    if (ty < 0) continue;
    for (double x = std::floor(lo.x); x <= hi.x; x += 1.0) {
      bool mirrored_x;
      const std::int64_t tx = texel_along(std::int64_t(x), width_, wrap_s_, true, &mirrored_x);
      if (tx < 0) continue;
      const CellPlace place = places(x, y);
      if (place.outside) continue;
      std::uint16_t claimed = 0;
      if (place.inside()) {
        claimed = kAllClaimPoints;
      } else {
        for (int j = 0; j < kClaimPoints; ++j)
          for (int i = 0; i < kClaimPoints; ++i) {
            // Sample point (i, j) of the texel, where this cell holds it (mirrored cells hold it mirrored).
            const double px = mirrored_x ? 1.0 - claim_offset(i) : claim_offset(i);
            const double py = mirrored_y ? 1.0 - claim_offset(j) : claim_offset(j);
            if (inside({x + px, y + py}, place.edges_across)) claimed |= std::uint16_t(1u << (j * kClaimPoints + i));
          }
      }
      const std::size_t texel = std::size_t(ty) * std::size_t(width_) + std::size_t(tx);
      twice[texel] |= once[texel] & claimed;
      again = again || (once[texel] & claimed) != 0;
      once[texel] |= claimed;
    }
  }
  return again;
}

std::optional<SurfacePoint> TexelLayout::point(std::size_t texel, const std::array<double, 4>& random) const {
  const auto first = pieces_.begin() + std::ptrdiff_t(piece_start_[texel]);
  const auto last = pieces_.begin() + std::ptrdiff_t(piece_start_[texel + 1]);
  if (first == last) return std::nullopt;
  // A piece with probability proportional to its surface's area; what is left
  // of random[0] within it picks a triangle of its fan the same way.
  const auto [chosen, rest] = pick_by_area(first, last, random[0]);

  const Corners& c = corners_[chosen->triangle];
  Polygon triangle;
  triangle.n = 3;
  std::copy(c.begin(), c.end(), triangle.p);
  const Polygon piece = clip_to_cell(triangle, chosen->cell_x, chosen->cell_y);
  const double piece_area = area(piece);
  int fan = 1;
  for (double so_far = 0.0; fan + 2 < piece.n; ++fan) {
    const double a = 0.5 * std::abs(cross(piece.p[fan] - piece.p[0], piece.p[fan + 1] - piece.p[0])) / piece_area;
    if (rest < so_far + a) break;
    so_far += a;
  }
  // Uniform in the fan's triangle (p0, p[fan], p[fan + 1]).
  const double s = std::sqrt(random[1]);
  const glm::dvec2 q = (1.0 - s) * piece.p[0] + s * (1.0 - random[2]) * piece.p[fan] + s * random[2] * piece.p[fan + 1];
  // Its barycentric weights in the whole triangle.
  const double d = cross(c[1] - c[0], c[2] - c[0]);
  const double b1 = std::clamp(cross(q - c[0], c[2] - c[0]) / d, 0.0, 1.0);
  const double b2 = std::clamp(cross(c[1] - c[0], q - c[0]) / d, 0.0, 1.0 - b1);
  return SurfacePoint{triangles_[chosen->triangle], float(b1), float(b2)};
}

}  // namespace mbao
