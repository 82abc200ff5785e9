#pragma once
// The trackers `probeless eval tracking` and `bench tracking` compare on the same frames
// (docs/tracking.md "Evaluation"): the shipped dense tracker on the OpenCL device (`dense`)
// and as its C++ reference (`dense_cpu`), and OpenCV 4.6 contrib's frame-to-frame odometry
// with its default parameters (`opencv_rgbd`, `opencv_icp`, `opencv_rgbdicp`).
#include <memory>
#include <string>
#include <vector>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"
#include "core/time.hpp"

namespace probeless {
class ComputeContext;
}

namespace probeless::eval {

// Every method sees depth only inside this range (metres): the dense tracker's defaults
// (kernels/tracking/dense_tracker.hpp), given to OpenCV's min/max depth too.
struct TrackingDepthRange {
  float min_m = 0.3f;
  float max_m = 4.0f;
};

struct TrackingStep {
  Pose T_world_camera;  // the first frame's camera is the world
  bool lost = false;    // no pose for this frame: T_world_camera is the last good one
  int keyframe = -1;    // the dense tracker's reference (its frame number); -1: none
};

class TrackingMethod {
 public:
  virtual ~TrackingMethod() = default;
  virtual const std::string& name() const = 0;
  virtual TrackingStep track(const ImageRGB8& colour, const DepthImage& depth_mm,
                             TimestampNs timestamp_ns) = 0;
  // Forget the past: the next frame is a first frame again.
  virtual void reset() = 0;
};

// dense dense_cpu opencv_rgbd opencv_icp opencv_rgbdicp, the default set and report order.
const std::vector<std::string>& tracking_method_names();

// Throws std::invalid_argument for an unknown name. `ctx` is needed by `dense` only.
// `rolling_shutter_readout_s`: the sequence's (TrackingSequence), used by the dense tracker.
std::unique_ptr<TrackingMethod> make_tracking_method(const std::string& name,
                                                     const PinholeIntrinsics& camera,
                                                     const TrackingDepthRange& range,
                                                     ComputeContext* ctx,
                                                     double rolling_shutter_readout_s = 0.0);

// "dense,opencv_icp" -> names, checked against tracking_method_names(); throws
// std::invalid_argument naming an unknown one or an empty list.
std::vector<std::string> parse_tracking_methods(const std::string& list);

}  // namespace probeless::eval
