#include "bake/lightmap_uvs.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>

#include "bake/chart_packing.h"
#include "bake/uv_charts.h"

namespace mbao {
namespace {

// A round's charts: each one's triangles (local indices), and those laid flat in its plane, in their order.
struct Charts {
  std::vector<std::vector<std::uint32_t>> members;
  std::vector<FlatChart> flat;
};

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

CutLengths cut_lengths(const std::vector<FlatChart>& charts, int width, int height, int padding) {
  const double texel = 1.0 / filling_density(charts, width, height), side = std::min(width, height) * texel;
  return {kStripShare * side, kHollowPaddings * std::max(padding, 1) * texel, kLargeShare * side};
}

// The area of a chart's triangles.
double triangles_area(const FlatChart& chart) {
  double sum = 0.0;
  for (std::size_t i = 0; i + 2 < chart.corners.size(); i += 3) {
    const glm::dvec2 a = chart.corners[i + 1] - chart.corners[i], b = chart.corners[i + 2] - chart.corners[i];
    sum += 0.5 * std::abs(a.x * b.y - a.y * b.x);
  }
  return sum;
}

// A long strip (a moulding, a rim) would set the density for every chart.
bool is_strip(const FlatChart& flat, const CutLengths& lengths) {
  return flat.size.x > lengths.strip && flat.size.x > 2.0 * flat.size.y;
}

// A hollow chart (a rose window, a column's capital) holds its box's middle
// empty, where it is long against the padding that cutting adds. A large one
// (a room's wall) is cut where `cut_large`: a few of them tile a square badly,
// but one alone tiles it well. Either packs better in pieces, however long.
bool hollow_or_large(const FlatChart& flat, const CutLengths& lengths, bool cut_large) {
  const double length = flat.size.x;
  return (length > lengths.hollow && triangles_area(flat) < kHollowFill * box_area(flat)) ||
         (cut_large && length > lengths.large);
}

// A strip's pieces must be shorter than this share of it: a piece whose
// triangles span the strip (a long quad's two) shortens nothing.
constexpr double kShorterPiece = 0.9;

bool pieces_shorter(const std::vector<FlatChart>& pieces, const FlatChart& flat) {
  return std::all_of(pieces.begin(), pieces.end(),
                     [&](const FlatChart& piece) { return piece.size.x < kShorterPiece * flat.size.x; });
}

// A chart's triangles and how they lie flat, as charts: while worth cutting,
// cut across into pieces no longer than a strip may be (two at least) and
// those into connected parts, each projected anew along a projected chart's
// axis (it may turn), or where the chart's conformal map laid it, turned anew.
class Cutter {
 public:
  Cutter(const ChartSurface& surface, const CutLengths& lengths, bool cut_large)
      : surface_(surface), lengths_(lengths), cut_large_(cut_large) {}

  void add(std::vector<std::uint32_t> members, FlatChart flat, const std::optional<glm::dvec3>& axis,
           Charts* charts) const {
    const bool in_pieces_however_long = hollow_or_large(flat, lengths_, cut_large_);
    std::vector<std::vector<std::uint32_t>> pieces;
    std::vector<FlatChart> laid;
    if (in_pieces_however_long || is_strip(flat, lengths_)) {
      const auto count = std::max<std::size_t>(2, std::size_t(std::ceil(flat.size.x / lengths_.strip)));
      pieces = connected_parts(shortened_cuts(cut_across(members, flat, count), surface_), surface_);
      for (const std::vector<std::uint32_t>& piece : pieces)
        laid.push_back(axis ? projected_flat(surface_, piece, *axis) : piece_flat(members, flat, piece));
    }
    // Not worth cutting; or one piece, where a triangle spans the length; or a strip's pieces no shorter.
    if (pieces.size() < 2 || !(in_pieces_however_long || pieces_shorter(laid, flat))) {
      charts->members.push_back(std::move(members));
      charts->flat.push_back(std::move(flat));
      return;
    }
    for (std::size_t p = 0; p < pieces.size(); ++p) add(std::move(pieces[p]), std::move(laid[p]), axis, charts);
  }

 private:
  const ChartSurface& surface_;
  CutLengths lengths_;
  bool cut_large_;
};

Charts cut_charts(const ChartSurface& surface, const LaidCharts& laid, const CutLengths& lengths, bool cut_large) {
  const Cutter cutter(surface, lengths, cut_large);
  Charts charts;
  for (std::size_t c = 0; c < laid.members.size(); ++c)
    cutter.add(laid.members[c], laid.flat[c], laid.axes[c], &charts);
  return charts;
}

bool has_large(const Charts& charts, const CutLengths& lengths) {
  return std::any_of(charts.flat.begin(), charts.flat.end(),
                     [&](const FlatChart& flat) { return flat.size.x > lengths.large; });
}

// Charts largest first by a measure of their boxes, so that small ones fill
// the gaps large ones leave.
template <typename Measure>
std::vector<std::size_t> largest_first(const std::vector<FlatChart>& charts, Measure measure) {
  std::vector<std::size_t> order(charts.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return measure(charts[a]) > measure(charts[b]); });
  return order;
}

std::vector<std::size_t> largest_box_first(const std::vector<FlatChart>& charts) {
  return largest_first(charts, box_area);
}

// The orders the charts are packed in: by box area, by long side (its x), by
// half perimeter. Which packs densest depends on the charts' shapes, and none
// did on every scene.
std::vector<std::vector<std::size_t>> packing_orders(const std::vector<FlatChart>& charts) {
  return {largest_box_first(charts), largest_first(charts, [](const FlatChart& c) { return c.size.x; }),
          largest_first(charts, [](const FlatChart& c) { return c.size.x + c.size.y; })};
}

// The least density tried: charts of more than 1e-270 world units still get boxes of 2 texels.
constexpr double kLeastDensity = 1e-30;

// Whether the charts fit at some density above 0, `padding` apart: each a
// texel in a box of 2 x 2 (1 x 1 where it has no extent). At density 0 itself
// every chart would shrink to a point, which covers no texel.
bool fit_at_all(const std::vector<FlatChart>& charts, int width, int height, int padding) {
  return packed_charts(charts, largest_box_first(charts), kLeastDensity, width, height, padding).has_value();
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

// The density's bisection ends where it changes it by less than 0.1%.
constexpr double kDensityPrecision = 1.001;

// The largest density between `lo`, at which the charts fit in `order`
// (where `placed` holds them), and `hi`, at which they are taken not to, to
// within kDensityPrecision, by bisection in ratio; and where each goes there.
double bisected_density(const std::vector<FlatChart>& charts, const std::vector<std::size_t>& order, double lo,
                        double hi, int width, int height, int padding, std::vector<Placement>* placed) {
  while (hi > kDensityPrecision * lo) {
    const double middle = std::sqrt(lo * hi);
    if (std::optional<std::vector<Placement>> fits = packed_charts(charts, order, middle, width, height, padding)) {
      lo = middle;
      *placed = std::move(*fits);
    } else {
      hi = middle;
    }
  }
  return lo;
}

// The largest density at which the charts fit `padding` apart in `order`
// (they must fit at kLeastDensity), and where each goes: halving from `most`
// until they fit, then by bisection.
double densest_in_order(const std::vector<FlatChart>& charts, const std::vector<std::size_t>& order, double most,
                        int width, int height, int padding, std::vector<Placement>* placed) {
  double hi = most, lo = 0.5 * hi;
  std::optional<std::vector<Placement>> fits;
  for (; lo > kLeastDensity && !(fits = packed_charts(charts, order, lo, width, height, padding)); lo *= 0.5) hi = lo;
  if (!fits) {
    lo = kLeastDensity;
    fits = packed_charts(charts, order, lo, width, height, padding);
  }
  *placed = std::move(*fits);
  return bisected_density(charts, order, lo, hi, width, height, padding, placed);
}

// The largest density above `to_beat` (none: any) at which the charts fit
// `padding` apart in any of the packing orders, and where each goes; none
// where no order fits them denser. An order is searched only from a density
// above the best so far, so that one which cannot beat it costs one packing.
std::optional<double> densest_packing(const std::vector<FlatChart>& charts, int width, int height, int padding,
                                      std::optional<double> to_beat, std::vector<Placement>* placed) {
  const double most = 2.0 * filling_density(charts, width, height);
  std::optional<double> density;
  for (const std::vector<std::size_t>& order : packing_orders(charts)) {
    const std::optional<double> best = density ? density : to_beat;
    if (!best) {
      density = densest_in_order(charts, order, most, width, height, padding, placed);
      continue;
    }
    const double denser = kDensityPrecision * *best;
    if (std::optional<std::vector<Placement>> fits = packed_charts(charts, order, denser, width, height, padding)) {
      *placed = std::move(*fits);
      density = bisected_density(charts, order, denser, std::max(most, 2.0 * denser), width, height, padding, placed);
    }
  }
  return density;
}

std::vector<glm::vec2> chart_uvs(const Charts& charts, const std::vector<Placement>& placed, double density,
                                 std::size_t triangles, int width, int height) {
  std::vector<glm::vec2> uvs(3 * triangles, glm::vec2(0.0f));
  for (std::size_t c = 0; c < charts.members.size(); ++c) {
    // Half a texel in from the box's corner: the box is a texel larger than the chart.
    const glm::dvec2 origin = glm::dvec2(placed[c].corner) + 0.5;
    const FlatChart flat = turned(charts.flat[c], placed[c].quarter_turns);
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
  double worst_stretch = 1.0;  // the charts' (LaidCharts)
};

// The area of the charts' triangles, in world units.
double triangles_area(const std::vector<FlatChart>& charts) {
  double area = 0.0;
  for (const FlatChart& chart : charts) area += triangles_area(chart);
  return area;
}

// The texels a packing's triangles cover, near enough: their area in the texture.
double texel_area(const Packing& packing) {
  return triangles_area(packing.charts.flat) * packing.density * packing.density;
}

// The charts packed, where they pack better than `rival`: at a larger
// padding, or at the same one covering more texels (charts laid flat
// differently differ in area at one density); none where they do not, or do
// not fit even touching.
std::optional<Packing> packing(Charts charts, int width, int height, int padding, const std::optional<Packing>& rival) {
  const std::optional<int> fitting = fitting_padding(charts.flat, width, height, padding);
  if (!fitting || (rival && *fitting < rival->padding)) return std::nullopt;
  std::optional<double> to_beat;  // the density at which they would cover the rival's texels
  if (rival && *fitting == rival->padding) {
    const double area = triangles_area(charts.flat), rival_texels = texel_area(*rival);
    if (area == 0.0) return std::nullopt;  // they cover no texel, so not more
    if (rival_texels > 0.0) to_beat = std::sqrt(rival_texels / area);
  }
  Packing packing;
  packing.padding = *fitting;
  const std::optional<double> density =
      densest_packing(charts.flat, width, height, packing.padding, to_beat, &packing.placed);
  if (!density) return std::nullopt;
  packing.density = *density;
  if (packing.padding < padding) packing.size_keeping_padding = size_keeping(charts.flat, width, height, padding);
  packing.charts = std::move(charts);
  return packing;
}

// The round's charts packed, with large charts cut or not, whichever packs
// better (uncut where they tie), where that is better than `rival`.
std::optional<Packing> best_packing(const ChartSurface& surface, const LaidCharts& laid, int width, int height,
                                    int padding, const std::optional<Packing>& rival) {
  const CutLengths lengths = cut_lengths(laid.flat, width, height, padding);
  Charts whole = cut_charts(surface, laid, lengths, false);
  const bool large = has_large(whole, lengths);
  std::optional<Packing> packed = packing(std::move(whole), width, height, padding, rival);
  if (large)
    if (std::optional<Packing> cut =
            packing(cut_charts(surface, laid, lengths, true), width, height, padding, packed ? packed : rival))
      packed = std::move(cut);
  if (packed) packed->worst_stretch = laid.worst_stretch;
  return packed;
}

// The round's charts grown in cones and projected, or laid flat by conformal
// maps, whichever packs better (the projected where they tie).
Packing round_packing(const ChartSurface& surface, const std::vector<int>& round, int width, int height, int padding) {
  const LaidCharts projected = projected_charts(surface, round);
  std::optional<Packing> packed = best_packing(surface, projected, width, height, padding, std::nullopt);
  if (std::optional<Packing> conformal =
          best_packing(surface, conformal_charts(surface, round), width, height, padding, packed))
    packed = std::move(conformal);
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
  const ChartSurface surface = chart_surface(mesh, triangles);
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
