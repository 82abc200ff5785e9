#include "core/beyond_range.hpp"

#include <algorithm>
#include <cmath>

namespace probeless {

int beyond_range_rim_px(const BeyondRangeRule& rule, int width) {
  if (rule.rim_px_at_640 <= 0 || width <= 0) return 0;
  return std::max(1, static_cast<int>(std::lround(double(rule.rim_px_at_640) * width / 640.0)));
}

std::size_t fill_beyond_range_holes(DepthImage& depth, const BeyondRangeRule& rule,
                                    BeyondRangeScratch& scratch) {
  if (rule.far_mm == 0) return 0;
  const int w = depth.width(), h = depth.height();
  const int rim_px = beyond_range_rim_px(rule, w);
  const std::size_t n = depth.pixel_count();
  const std::uint16_t* d = depth.data();
  // Most frames indoors measure nothing that far: then no hole can be filled (0.02 ms against
  // the 1.2 ms of the full pass on a VGA frame a third hole, tests/unit/core DISABLED_CostVga).
  if (std::none_of(d, d + n, [&](std::uint16_t v) { return v >= rule.far_mm; })) return 0;
  // Every hole pixel takes the depth of its nearest measured pixel (4-connected steps through
  // the hole, breadth first from the rim): `nearest` holds it, 0 while unreached.
  std::vector<std::uint16_t>& nearest = scratch.nearest;
  std::vector<std::uint32_t>& queue = scratch.queue;
  std::vector<std::uint16_t>& steps = scratch.steps;  // from the rim, 1 on it
  nearest.assign(n, 0);
  steps.assign(n, 0);
  queue.clear();
  const auto neighbours = [&](std::size_t p, auto&& f) {
    const int x = static_cast<int>(p % static_cast<std::size_t>(w));
    const int y = static_cast<int>(p / static_cast<std::size_t>(w));
    if (x > 0) f(p - 1);
    if (x + 1 < w) f(p + 1);
    if (y > 0) f(p - static_cast<std::size_t>(w));
    if (y + 1 < h) f(p + static_cast<std::size_t>(w));
  };
  for (std::size_t p = 0; p < n; ++p) {
    if (d[p] != 0) continue;
    std::uint16_t rim = 0;  // the farthest measured 4-neighbour: a wall fading out wins ties
    neighbours(p, [&](std::size_t q) { rim = std::max(rim, d[q]); });
    if (rim == 0) continue;
    nearest[p] = rim;
    steps[p] = 1;
    queue.push_back(static_cast<std::uint32_t>(p));
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::uint32_t p = queue[head];
    neighbours(p, [&](std::size_t q) {
      if (d[q] != 0 || nearest[q] != 0) return;
      nearest[q] = nearest[p];
      steps[q] = static_cast<std::uint16_t>(std::min(65535, steps[p] + 1));
      queue.push_back(static_cast<std::uint32_t>(q));
    });
  }
  std::size_t filled = 0;
  std::uint16_t* out = depth.data();
  for (const std::uint32_t p : queue)
    if (nearest[p] >= rule.far_mm && steps[p] > rim_px) out[p] = nearest[p], ++filled;
  return filled;
}

}  // namespace probeless
