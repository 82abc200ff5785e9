#include "core/beyond_range.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace probeless {

int beyond_range_rim_px(const BeyondRangeRule& rule, int width) {
  if (rule.rim_px_at_640 <= 0 || width <= 0) return 0;
  return std::max(1, static_cast<int>(std::lround(double(rule.rim_px_at_640) * width / 640.0)));
}

bool measures_beyond_range(const DepthImage& depth, const BeyondRangeRule& rule) {
  if (rule.far_mm == 0) return false;
  const std::uint16_t* d = depth.data();
  return std::any_of(d, d + depth.pixel_count(), [&](std::uint16_t v) { return v >= rule.far_mm; });
}

std::size_t fill_beyond_range_holes(DepthImage& depth, const BeyondRangeRule& rule,
                                    BeyondRangeScratch& scratch) {
  if (rule.far_mm == 0) return 0;
  const int w = depth.width(), h = depth.height();
  const int rim_px = beyond_range_rim_px(rule, w);
  if (w > 65535 || h > 65535)  // the queue packs x and y in 16 bits each
    throw std::invalid_argument("fill_beyond_range_holes: a depth image over 65535 px a side");
  const std::size_t n = depth.pixel_count();
  const std::uint16_t* d = depth.data();
  // Most frames indoors measure nothing that far: then no hole can be filled (0.02 ms against
  // the ~1 ms of the full pass on a VGA frame a third hole, tests/unit/core DISABLED_CostVga).
  if (!measures_beyond_range(depth, rule)) return 0;
  // Every hole pixel takes the depth of its nearest measured pixel (4-connected steps through
  // the hole, breadth first from the rim). `reached` packs that depth and the steps from the
  // rim (1 on it) as depth << 16 | steps, 0 while unreached. It is all zeros between calls: the
  // queue lists every pixel written, and they are reset at the end, so a frame pays for its
  // holes, not for clearing two frame-sized arrays (in `perf` of `bench pipeline` the memsets
  // cost as much as the search).
  std::vector<std::uint32_t>& reached = scratch.reached;
  std::vector<std::uint32_t>& queue = scratch.queue;
  if (reached.size() != n) reached.assign(n, 0);
  queue.clear();
  // The queue holds (y << 16 | x): the neighbours' bounds come from x and y without a division
  // per pixel: 1.05 -> 0.85 ms p50 on a VGA frame a third hole (DISABLED_CostVga, 2026-11-27).
  const auto uw = static_cast<std::size_t>(w);
  const auto neighbours = [&](int x, int y, auto&& f) {
    const std::size_t p = static_cast<std::size_t>(y) * uw + static_cast<std::size_t>(x);
    if (x > 0) f(p - 1, x - 1, y);
    if (x + 1 < w) f(p + 1, x + 1, y);
    if (y > 0) f(p - uw, x, y - 1);
    if (y + 1 < h) f(p + uw, x, y + 1);
  };
  const auto pack = [](int x, int y) {
    return static_cast<std::uint32_t>(y) << 16 | static_cast<std::uint32_t>(x);
  };
  for (int y = 0; y < h; ++y) {
    const std::uint16_t* row = d + static_cast<std::size_t>(y) * uw;
    for (int x = 0; x < w; ++x) {
      if (row[x] != 0) continue;
      std::uint16_t rim = 0;  // the farthest measured 4-neighbour: a wall fading out wins ties
      neighbours(x, y, [&](std::size_t q, int, int) { rim = std::max(rim, d[q]); });
      if (rim == 0) continue;
      reached[static_cast<std::size_t>(y) * uw + static_cast<std::size_t>(x)] =
          std::uint32_t{rim} << 16 | 1u;
      queue.push_back(pack(x, y));
    }
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int x = static_cast<int>(queue[head] & 0xffffu), y = static_cast<int>(queue[head] >> 16);
    const std::uint32_t from =
        reached[static_cast<std::size_t>(y) * uw + static_cast<std::size_t>(x)];
    // One more step, saturating at 65535 as a 16-bit count.
    const std::uint32_t next = (from & 0xffffu) == 0xffffu ? from : from + 1;
    neighbours(x, y, [&](std::size_t q, int qx, int qy) {
      if (d[q] != 0 || reached[q] != 0) return;
      reached[q] = next;
      queue.push_back(pack(qx, qy));
    });
  }
  std::size_t filled = 0;
  std::uint16_t* out = depth.data();
  const auto far = static_cast<std::uint32_t>(rule.far_mm);
  const auto rim_steps = static_cast<std::uint32_t>(rim_px);
  for (const std::uint32_t packed : queue) {
    const std::size_t p = static_cast<std::size_t>(packed >> 16) * uw + (packed & 0xffffu);
    const std::uint32_t nearest = reached[p] >> 16, steps = reached[p] & 0xffffu;
    if (nearest >= far && steps > rim_steps) out[p] = static_cast<std::uint16_t>(nearest), ++filled;
    reached[p] = 0;
  }
  return filled;
}

}  // namespace probeless
