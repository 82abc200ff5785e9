#pragma once
// The device stage of hole_core_reference.hpp: the real depth with the cores of wide holes set
// nearer than anything, before CVF's depth test. Two small kernels (a dilation of bit sets along
// the rows, then a sliding count down the columns), and two more for the near occluder's rim
// (mark_near_occluders()).
#include <optional>

#include "core/pixel_rect.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::occlusion {

class HoleCoreFill {
 public:
  explicit HoleCoreFill(ComputeContext& ctx);
  // The filled copy of `depth` for a window radius >= 1 px (valid until the next call; else
  // std::invalid_argument); enqueues and does not wait.
  // With `colour` (same size), holes of a far surface's colour are no core candidates
  // (far_hole_colour(), hole_core_reference.hpp).
  // With `needed`, only the pixels inside it are written and right (the rest holds whatever
  // an earlier call left): CVF reads the real depth only on the virtual object (its depth test
  // is "ignore" elsewhere), so it asks for the objects' rectangle; the pass was 5.4 % of
  // `bench pipeline`'s CPU samples over the whole frame.
  const DeviceImage<std::uint16_t, 1>& run(const DeviceImage<std::uint16_t, 1>& depth, int radius,
                                           const DeviceImage<std::uint8_t, 3>* colour = nullptr,
                                           const std::optional<PixelRect>& needed = std::nullopt);
  // The last run()'s filled depth with the near occluders' rims marked too
  // (mark_near_occluders_reference(): with `colour`, the same as run()'s, the holes near a
  // core that take the core's colour, marked in place in run()'s image, which is returned:
  // rows without a core within r are not touched; without colour, every hole with a core
  // within r, in an image of its own); valid until the next call. Right inside run()'s `needed`
  // only (the filled depth is computed r px around it for this pass). Throws std::invalid_argument
  // for a colour of another size, or a radius above 128 px with colour (the row sums are 16-bit).
  const DeviceImage<std::uint16_t, 1>& mark_near_occluders(
      const DeviceImage<std::uint8_t, 3>* colour = nullptr);

 private:
  // out = NEAR where the window of `depth` holds only (need_all) or some `value` and depth
  // is unknown or NEAR there, else depth.
  void window_pass(const DeviceImage<std::uint16_t, 1>& depth, std::uint16_t value, bool need_all,
                   DeviceImage<std::uint16_t, 1>& out, int radius,
                   const DeviceImage<std::uint8_t, 3>* colour, const PixelRect& needed);

  ComputeContext& ctx_;
  ::cl::Kernel rows_, fill_, rim_rows_, rim_mark_;
  int radius_ = 0;
  PixelRect needed_;  // run()'s, clipped to the frame
  DeviceImage<std::uint8_t, 1> row_hits_;
  DeviceImage<std::uint16_t, 8> rim_sums_;                // near_rim_rows' window sums
  const DeviceImage<std::uint16_t, 1>* depth_ = nullptr;  // run()'s
  ::cl::Buffer core_rows_;       // per row: 1 if the cores' pass made a core there
  ::cl::Buffer rim_rows_flags_;  // per row: 1 if a core is within r rows (near_rim_rows)
  int core_rows_size_ = 0;
  DeviceImage<std::uint16_t, 1> filled_, marked_;
};

}  // namespace probeless::occlusion
