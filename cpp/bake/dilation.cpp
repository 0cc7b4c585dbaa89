#include "bake/dilation.h"

#include <algorithm>

namespace mbao {

std::vector<std::uint8_t> dilate(const std::vector<std::uint8_t>& covered, int width, int height, int padding,
                                 const std::vector<std::vector<float>*>& channels) {
  std::vector<std::uint8_t> filled(covered.size(), 0);
  const auto at = [width](int x, int y) { return std::size_t(y) * std::size_t(width) + std::size_t(x); };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (covered[at(x, y)]) continue;
      int best = -1, best_distance = 0;
      for (int sy = std::max(0, y - padding); sy <= std::min(height - 1, y + padding); ++sy)
        for (int sx = std::max(0, x - padding); sx <= std::min(width - 1, x + padding); ++sx) {
          const int distance = (sx - x) * (sx - x) + (sy - y) * (sy - y);
          if (covered[at(sx, sy)] && (best < 0 || distance < best_distance)) {
            best = int(at(sx, sy));
            best_distance = distance;
          }
        }
      if (best < 0) continue;
      filled[at(x, y)] = 1;
      // Sources are covered texels, which this never writes: the order of filling does not matter.
      for (std::vector<float>* channel : channels) (*channel)[at(x, y)] = (*channel)[std::size_t(best)];
    }
  return filled;
}

}  // namespace mbao
