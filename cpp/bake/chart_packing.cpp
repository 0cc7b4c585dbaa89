#include "bake/chart_packing.h"

#include <algorithm>
#include <climits>
#include <cmath>

namespace mbao {
namespace {

// The texels a chart's triangles touch at a density, per column of its box:
// every texel whose square meets a triangle, so that two charts whose touched
// texels differ claim no texel centre in common whatever their edges' rounding.
struct Outline {
  int width = 0, height = 0;      // its box, in texels
  std::vector<int> top, bottom;   // per column: the first and last row touched; top > bottom where none
};

// The rows of column [x, x + 1] that triangle (a, b, c) meets: the y extent of
// its part in the column, which is convex, so each row in between meets it.
void touch_column(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, int x, Outline* outline) {
  double lo = INFINITY, hi = -INFINITY;
  const glm::dvec2 corners[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 p = corners[k], q = corners[(k + 1) % 3];
    if (p.x >= x && p.x <= x + 1) {
      lo = std::min(lo, p.y);
      hi = std::max(hi, p.y);
    }
    for (const double side : {double(x), double(x + 1)})  // where the edge crosses the column's sides
      if ((p.x - side) * (q.x - side) < 0.0) {
        const double y = p.y + (q.y - p.y) * (side - p.x) / (q.x - p.x);
        lo = std::min(lo, y);
        hi = std::max(hi, y);
      }
  }
  if (!(lo <= hi)) return;
  const int first = std::clamp(int(std::floor(lo)), 0, outline->height - 1);
  const int last = std::clamp(std::max(first, int(std::ceil(hi)) - 1), 0, outline->height - 1);
  outline->top[std::size_t(x)] = std::min(outline->top[std::size_t(x)], first);
  outline->bottom[std::size_t(x)] = std::max(outline->bottom[std::size_t(x)], last);
}

Outline outline_of(const FlatChart& chart, double density) {
  Outline outline;
  outline.width = int(std::ceil(chart.size.x * density)) + 1;
  outline.height = int(std::ceil(chart.size.y * density)) + 1;
  outline.top.assign(std::size_t(outline.width), INT_MAX);
  outline.bottom.assign(std::size_t(outline.width), INT_MIN);
  for (std::size_t i = 0; i + 2 < chart.corners.size(); i += 3) {
    const glm::dvec2 a = chart.corners[i] * density + 0.5, b = chart.corners[i + 1] * density + 0.5,
                     c = chart.corners[i + 2] * density + 0.5;
    const int first = std::clamp(int(std::floor(std::min({a.x, b.x, c.x}))), 0, outline.width - 1);
    const int last = std::clamp(int(std::ceil(std::max({a.x, b.x, c.x}))) - 1, first, outline.width - 1);
    for (int x = first; x <= last; ++x) touch_column(a, b, c, x, &outline);
  }
  return outline;
}

// Per column of the box widened by `padding` each side: the first row (of
// the box) within `padding` texels of a touched texel; INT_MAX where none is.
std::vector<int> kept_clear_from(const Outline& outline, int padding) {
  std::vector<int> top(std::size_t(outline.width + 2 * padding), INT_MAX);
  for (int x = 0; x < outline.width; ++x) {
    if (outline.top[std::size_t(x)] > outline.bottom[std::size_t(x)]) continue;
    for (int j = x; j <= x + 2 * padding; ++j)
      top[std::size_t(j)] = std::min(top[std::size_t(j)], outline.top[std::size_t(x)] - padding);
  }
  return top;
}

}  // namespace

std::optional<std::vector<glm::ivec2>> packed_charts(const std::vector<FlatChart>& charts,
                                                     const std::vector<std::size_t>& order, double density,
                                                     int width, int height, int padding) {
  std::vector<glm::ivec2> placed(charts.size(), glm::ivec2(0));
  std::vector<int> skyline(std::size_t(width), 0);  // per column: the row below the lowest touched texel placed
  for (std::size_t c : order) {
    const Outline outline = outline_of(charts[c], density);
    const std::vector<int> clear = kept_clear_from(outline, padding);
    std::optional<glm::ivec2> best;
    for (int x = padding; x + outline.width + padding <= width; ++x) {
      const int* below = &skyline[std::size_t(x - padding)];
      int y = padding;
      for (std::size_t j = 0; j < clear.size() && (!best || y < best->y); ++j)  // no further once no higher
        if (clear[j] != INT_MAX) y = std::max(y, below[j] - clear[j]);
      if (!best || y < best->y) best = glm::ivec2(x, y);
    }
    if (!best || best->y + outline.height + padding > height) return std::nullopt;
    placed[c] = *best;
    for (int i = 0; i < outline.width; ++i)
      if (outline.top[std::size_t(i)] <= outline.bottom[std::size_t(i)]) {
        int& below = skyline[std::size_t(best->x + i)];
        below = std::max(below, best->y + outline.bottom[std::size_t(i)] + 1);
      }
  }
  return placed;
}

}  // namespace mbao
