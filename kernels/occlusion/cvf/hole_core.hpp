#pragma once
// The device stage of hole_core_reference.hpp: the real depth with the cores of wide holes set
// nearer than anything, before CVF's depth test. Two small kernels (a dilation of bit sets along
// the rows, then a sliding count down the columns).
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
  // The last run()'s filled depth with the holes around each core marked too
  // (mark_near_occluders_reference()); valid until the next call. Right inside run()'s
  // `needed` only (the filled depth is computed r px around it for this pass).
  const DeviceImage<std::uint16_t, 1>& mark_near_occluders();

 private:
  // out = NEAR where the window of `depth` holds only (need_all) or some `value` and depth
  // is unknown or NEAR there, else depth.
  void window_pass(const DeviceImage<std::uint16_t, 1>& depth, std::uint16_t value, bool need_all,
                   DeviceImage<std::uint16_t, 1>& out, int radius,
                   const DeviceImage<std::uint8_t, 3>* colour, const PixelRect& needed);

  ComputeContext& ctx_;
  ::cl::Kernel rows_, fill_;
  int radius_ = 0;
  PixelRect needed_;  // run()'s, clipped to the frame
  DeviceImage<std::uint8_t, 1> row_hits_;
  DeviceImage<std::uint16_t, 1> filled_, marked_;
};

}  // namespace probeless::occlusion
