#pragma once
// The temporal stabilisation stage (matte_stabiliser.cl; params and the idea in
// matte_stabiliser_params.hpp; docs/occlusion.md "Temporal stabilisation"). It keeps the
// previous frame's colour, real depth, on-object flags and stabilised matte on the device (the
// kernel's own output, two buffers used in turn); process() blends the current matte in place
// and remembers this frame. The first frame, and the first after reset(), passes through
// unchanged.
#include <optional>

#include "kernels/occlusion/common/occlusion_method.hpp"
#include "kernels/occlusion/temporal/matte_stabiliser_params.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless::occlusion {

class MatteStabiliser {
 public:
  MatteStabiliser(ComputeContext& ctx, StabiliserParams params = {});

  // `alpha`: the current frame's matte of `in` (every image one size, else
  // std::invalid_argument). `T_world_camera`: the colour camera's pose; without one the
  // motion since the previous frame is taken as none (identity). A frame of another size
  // than the previous one starts over. Only the rows of in.objects are visited (with those
  // the history buffer being written held the object at, to clear them): the matte outside
  // is left as it is, as it is off the object.
  void process(const OcclusionInputs& in, const PinholeIntrinsics& intrinsics,
               const std::optional<Pose>& T_world_camera, DeviceImage<float, 1>& alpha);
  // Forget the previous frame (the pose was lost, the source restarted).
  void reset() { have_previous_ = false; }
  const StabiliserParams& params() const { return params_; }

 private:
  ComputeContext& ctx_;
  StabiliserParams params_;
  ::cl::Kernel kernel_;
  bool have_previous_ = false;
  std::optional<Pose> previous_pose_;
  // Per pixel: the stabilised matte's bits | (r, g, b, on-object) << 32 (matte_stabiliser.cl),
  // and the real depth. [previous_] holds the previous frame, the other one is written.
  DeviceImage<std::uint64_t, 1> history_[2];
  DeviceImage<std::uint16_t, 1> depth_[2];
  // Per history buffer: the rows outside which it holds no on-object flag (the rows it was
  // last written over; the whole frame while its contents are undefined).
  PixelRect flagged_rows_[2];
  int previous_ = 0;
};

}  // namespace probeless::occlusion
