#include "bake/chart_packing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace mbao {
namespace {

// A grid of bits, a row of 64-bit words per row of texels, with a spare zero
// word at each row's end so that reading 64 bits from any column is one shift.
class BitGrid {
 public:
  BitGrid(int width, int height)
      : width_(width),
        height_(height),
        words_(std::size_t(width + 63) / 64 + 1),
        bits_(words_ * std::size_t(height), 0) {}

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t words() const { return words_; }
  const std::uint64_t* row(int y) const { return &bits_[std::size_t(y) * words_]; }
  bool test(int x, int y) const { return (row(y)[std::size_t(x) / 64] >> (x % 64)) & 1u; }
  // The first column of row y from x on whose bit is clear (set); the width where none.
  int next_clear(int x, int y) const { return next(x, y, ~std::uint64_t(0)); }
  int next_set(int x, int y) const { return next(x, y, 0); }
  void set(int x, int y) { bits_[std::size_t(y) * words_ + std::size_t(x) / 64] |= std::uint64_t(1) << (x % 64); }
  // Sets in row y the bits set in `source`'s row, moved `x` columns on.
  void set_row(const BitGrid& source, int source_y, int x, int y) {
    std::uint64_t* to = &bits_[std::size_t(y) * words_];
    const std::uint64_t* from = source.row(source_y);
    const std::size_t word = std::size_t(x) / 64;
    const int shift = x % 64;
    for (std::size_t k = 0; k + 1 < source.words(); ++k) {  // the spare word is zero
      if (!from[k]) continue;
      to[word + k] |= from[k] << shift;
      if (shift) to[word + k + 1] |= from[k] >> (64 - shift);
    }
  }
  // The first column of the run of set bits in row y that holds column x (set).
  int run_start(int x, int y) const {
    const std::uint64_t* r = row(y);
    std::size_t k = std::size_t(x) / 64;
    const int bit = x % 64;
    std::uint64_t clear = ~r[k] & (bit == 63 ? ~std::uint64_t(0) : (std::uint64_t(2) << bit) - 1);
    for (; !clear; clear = ~r[k])
      if (k-- == 0) return 0;
    return int(64 * k) + 64 - __builtin_clzll(clear);
  }
  // The 64 bits of row y from column x on.
  std::uint64_t bits_from(int x, int y) const {
    const std::uint64_t* r = row(y) + std::size_t(x) / 64;
    const int shift = x % 64;
    return shift == 0 ? r[0] : (r[0] >> shift) | (r[1] << (64 - shift));
  }

 private:
  int next(int x, int y, std::uint64_t flip) const {
    const std::uint64_t* r = row(y);
    for (std::size_t k = std::size_t(x) / 64; k < words_ && x < width_; ++k, x = int(64 * k)) {
      const std::uint64_t bits = (r[k] ^ flip) >> (x % 64);
      if (bits) return std::min(width_, x + __builtin_ctzll(bits));
    }
    return width_;
  }

  int width_, height_;
  std::size_t words_;
  std::vector<std::uint64_t> bits_;
};

// The texels a chart's triangles touch at a density, in its box: every texel
// whose square meets a triangle, so that two charts whose touched texels
// differ claim no texel centre in common whatever their edges' rounding.
// Column by column: a triangle's part in a column is convex, so each row
// between its lowest and highest meets it.
BitGrid touched_texels(const FlatChart& chart, double density) {
  BitGrid grid(int(std::ceil(chart.size.x * density)) + 1, int(std::ceil(chart.size.y * density)) + 1);
  for (std::size_t i = 0; i + 2 < chart.corners.size(); i += 3) {
    const glm::dvec2 corners[3] = {chart.corners[i] * density + 0.5, chart.corners[i + 1] * density + 0.5,
                                   chart.corners[i + 2] * density + 0.5};
    const double left = std::min({corners[0].x, corners[1].x, corners[2].x});
    const double right = std::max({corners[0].x, corners[1].x, corners[2].x});
    const int first = std::clamp(int(std::floor(left)), 0, grid.width() - 1);
    const int last = std::clamp(int(std::ceil(right)) - 1, first, grid.width() - 1);
    for (int x = first; x <= last; ++x) {
      double lo = INFINITY, hi = -INFINITY;
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
      if (!(lo <= hi)) continue;
      const int top = std::clamp(int(std::floor(lo)), 0, grid.height() - 1);
      const int bottom = std::clamp(std::max(top, int(std::ceil(hi)) - 1), 0, grid.height() - 1);
      for (int y = top; y <= bottom; ++y) grid.set(x, y);
    }
  }
  return grid;
}

// The texels within `padding` of a set one in x and in y: the grid grown by `padding` each side.
BitGrid grown(const BitGrid& touched, int padding) {
  const int w = touched.width() + 2 * padding, h = touched.height() + 2 * padding;
  BitGrid across(w, touched.height());  // within `padding` in x
  for (int y = 0; y < touched.height(); ++y)
    for (int d = 0; d <= 2 * padding; ++d) across.set_row(touched, y, d, y);
  BitGrid clear(w, h);
  for (int y = 0; y < touched.height(); ++y)
    for (int d = 0; d <= 2 * padding; ++d) clear.set_row(across, y, 0, y + d);
  return clear;
}

// A chart at one density: the texels it touches, and those kept clear around them.
struct ChartTexels {
  // Two charts' touched texels lie more than `padding` apart in x or y where
  // those within padding / 2 of one's meet none within the rest of the other's.
  BitGrid touched, claimed, clear;
  std::vector<int> clear_runs;  // per row of `clear`: its longest run of set bits
  // The longest of those runs, the last of its length in the first row that has one: its row and start.
  int key_row = 0, key_start = 0;
};

ChartTexels chart_texels(const FlatChart& chart, double density, int padding) {
  ChartTexels texels{touched_texels(chart, density), BitGrid(0, 0), BitGrid(0, 0), {}};
  texels.claimed = grown(texels.touched, padding / 2);
  texels.clear = grown(texels.touched, padding - padding / 2);
  const BitGrid& clear = texels.clear;
  texels.clear_runs.assign(std::size_t(clear.height()), 0);
  int key_length = 0;
  for (int y = 0; y < clear.height(); ++y)
    for (int start = clear.next_set(0, y); start < clear.width();) {
      const int end = clear.next_clear(start, y);
      int& longest = texels.clear_runs[std::size_t(y)];
      longest = std::max(longest, end - start);
      if (end - start > key_length || (end - start == key_length && y == texels.key_row)) {
        key_length = end - start;
        texels.key_row = y;
        texels.key_start = start;
      }
      start = clear.next_set(end, y);
    }
  return texels;
}

// Unclaimed texels [start, end) of a row.
struct FreeRun {
  int start, end;
};

// The texture: the texels placed charts claim, and per row its runs of free ones.
class Atlas {
 public:
  Atlas(int width, int height)
      : claimed_(width, height),
        free_runs_(std::size_t(height), {FreeRun{0, width}}),
        longest_free_(std::size_t(height), width) {}

  // Where `chart`'s box's corner goes: the highest row up to `last_row`, then
  // the leftmost column, half `padding` (rounded up) from the border, at which
  // its kept-clear texels meet no claimed texel; none where it fits nowhere.
  // Only rows where each of its rows' runs could lie in a free run, and there
  // only columns where its longest run does, are tried.
  std::optional<glm::ivec2> first_fit(const ChartTexels& chart, int padding, int last_row) const {
    const int w = chart.touched.width(), h = chart.touched.height();
    // Of the kept-clear texels beyond the touched, and so of the box from the
    // border: under REPEAT, charts at opposite edges lie `padding` apart.
    const int reach = padding - padding / 2;
    const int key_length = chart.clear_runs[std::size_t(chart.key_row)];
    const int last_x = claimed_.width() - reach - w;  // the last corner column in the texture
    int meeting_row = 0;
    for (int y = reach; y + h + reach <= claimed_.height() && y <= last_row; ++y) {
      if (!rows_can_hold(chart, y - reach)) continue;
      for (const FreeRun& run : free_runs_[std::size_t(y - reach + chart.key_row)]) {
        if (run.end - run.start < key_length) continue;
        // Corners at which the key run lies in the free run.
        const int last = std::min(last_x, run.end - key_length - chart.key_start + reach);
        for (int x = std::max(reach, run.start - chart.key_start + reach); x <= last;) {
          const int next = first_clear_of_meetings(chart, x - reach, y - reach, meeting_row) + reach;
          if (next == x) return glm::ivec2(x, y);
          x = next;
        }
      }
    }
    return std::nullopt;
  }

  void place(const ChartTexels& chart, glm::ivec2 corner, int padding) {
    const glm::ivec2 from = corner - padding / 2;
    for (int y = 0; y < chart.claimed.height(); ++y) {
      claimed_.set_row(chart.claimed, y, from.x, from.y + y);
      update_free_runs(from.y + y);
    }
  }

 private:
  // Whether each row of the atlas from `top` has a free run as long as the
  // longest run of the chart's kept-clear texels in its row there.
  bool rows_can_hold(const ChartTexels& chart, int top) const {
    for (int r = 0; r < chart.clear.height(); ++r)
      if (longest_free_[std::size_t(top + r)] < chart.clear_runs[std::size_t(r)]) return false;
    return true;
  }

  // For the chart's kept-clear texels with their corner at x, y: x where
  // they meet no claimed texel, else the least x beyond it that might: past
  // the rightmost claimed texel met in a row that meets one, by the run of
  // kept-clear texels that met it. `meeting_row`, the row that met last, is
  // tried first: sliding along a row of the atlas, the same row of the chart
  // tends to meet again, and any row's meeting bounds the skip.
  int first_clear_of_meetings(const ChartTexels& chart, int x, int y, int& meeting_row) const {
    if (const int past = past_meeting(chart, x, y, meeting_row); past > x) return past;
    for (int r = 0; r < chart.clear.height(); ++r)
      if (const int past = past_meeting(chart, x, y, r); past > x) {
        meeting_row = r;
        return past;
      }
    return x;
  }

  // x where row r of the chart's kept-clear texels, with their corner at x, y,
  // meets no claimed texel; else past the rightmost one it meets, as above.
  int past_meeting(const ChartTexels& chart, int x, int y, int r) const {
    const std::uint64_t* wanted = chart.clear.row(r);
    for (std::size_t k = chart.clear.words(); k-- > 0;) {
      const std::uint64_t met = wanted[k] ? claimed_.bits_from(x + int(64 * k), y + r) & wanted[k] : 0;
      if (!met) continue;
      const int column = int(64 * k) + 63 - __builtin_clzll(met);
      return x + column - chart.clear.run_start(column, r) + 1;
    }
    return x;
  }

  void update_free_runs(int y) {
    std::vector<FreeRun>& runs = free_runs_[std::size_t(y)];
    runs.clear();
    longest_free_[std::size_t(y)] = 0;
    for (int start = claimed_.next_clear(0, y); start < claimed_.width();) {
      const int end = claimed_.next_set(start, y);
      runs.push_back({start, end});
      longest_free_[std::size_t(y)] = std::max(longest_free_[std::size_t(y)], end - start);
      start = claimed_.next_clear(end, y);
    }
  }

  BitGrid claimed_;                              // the texels placed charts claim
  std::vector<std::vector<FreeRun>> free_runs_;  // per row: its runs of unclaimed texels, left to right
  std::vector<int> longest_free_;                // per row: the longest of those
};

}  // namespace

FlatChart turned(const FlatChart& chart, int quarter_turns) {
  FlatChart result = chart;
  for (int k = 0; k < quarter_turns % 4; ++k) {
    for (glm::dvec2& q : result.corners) q = glm::dvec2(result.size.y - q.y, q.x);
    result.size = glm::dvec2(result.size.y, result.size.x);
  }
  return result;
}

// Whether corner a lies higher up than b, or as high and further left.
bool before(glm::ivec2 a, glm::ivec2 b) { return a.y < b.y || (a.y == b.y && a.x < b.x); }

std::optional<std::vector<Placement>> packed_charts(const std::vector<FlatChart>& charts,
                                                    const std::vector<std::size_t>& order, double density, int width,
                                                    int height, int padding) {
  std::vector<Placement> placed(charts.size());
  Atlas atlas(width, height);
  for (std::size_t c : order) {
    std::optional<ChartTexels> best;
    // Quarter turns only where a chart fits neither as it is nor half turned:
    // tried for every chart, they cost several times the packing's time for
    // little more of the texture covered (docs/limits.md).
    for (const int quarter_turns : {0, 2, 1, 3}) {
      if (quarter_turns == 1 && best) break;
      ChartTexels texels = chart_texels(turned(charts[c], quarter_turns), density, padding);
      const int last_row = best ? placed[c].corner.y : height;  // a turn is tried no lower
      const std::optional<glm::ivec2> corner = atlas.first_fit(texels, padding, last_row);
      if (corner && (!best || before(*corner, placed[c].corner))) {
        best = std::move(texels);
        placed[c] = Placement{*corner, quarter_turns};
      }
    }
    if (!best) return std::nullopt;
    atlas.place(*best, placed[c].corner, padding);
  }
  return placed;
}

}  // namespace mbao
