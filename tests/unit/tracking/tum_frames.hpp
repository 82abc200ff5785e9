#pragma once
// The TUM fr1/rpy frames of ../shared/data for the tracking tests: colour, depth in mm, the
// ground-truth pose, and the ATE after an SE(3) Umeyama alignment (Sturm et al. 2012).
#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <vector>

#include "core/camera/pinhole.hpp"
#include "drivers/io/png.hpp"
#include "drivers/replay/tum_source.hpp"
#include "support/test_data.hpp"

namespace probeless::testing {

inline constexpr const char* kTumRpy = "rgbd/tum_fr1_rpy";

// TUM's published fr1 colour intrinsics (distortion ignored, as the tracker does).
inline PinholeIntrinsics tum_fr1_camera() {
  return {640, 480, 517.3, 516.5, 318.6, 255.3};
}

struct TumFrame {
  ImageRGB8 colour;
  DepthImage depth_mm;
  TimestampNs timestamp_ns;
  std::optional<Pose> truth;
};

inline std::vector<TumFrame> read_tum_frames(std::size_t max_frames = 10000) {
  const auto seq = replay::open_tum_sequence(shared_data_dir() / kTumRpy);
  std::vector<TumFrame> frames;
  for (const auto& f : seq.frames) {
    if (frames.size() >= max_frames) break;
    frames.push_back({read_png_rgb8(seq.dir / f.colour),
                      replay::tum_depth_to_mm(read_png_depth16(seq.dir / f.depth)), f.timestamp_ns,
                      f.rig_pose});
  }
  return frames;
}

// RMSE of the positions after the rigid (no scale) alignment of `estimate` onto `truth`.
inline double ate_rmse(const std::vector<Eigen::Vector3d>& estimate,
                       const std::vector<Eigen::Vector3d>& truth) {
  Eigen::Matrix3Xd a(3, estimate.size()), b(3, truth.size());
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    a.col(Eigen::Index(i)) = estimate[i];
    b.col(Eigen::Index(i)) = truth[i];
  }
  const Eigen::Matrix4d T = Eigen::umeyama(a, b, false);
  const Eigen::Matrix3Xd aligned =
      (T.topLeftCorner<3, 3>() * a).colwise() + T.topRightCorner<3, 1>();
  return std::sqrt((aligned - b).colwise().squaredNorm().mean());
}

}  // namespace probeless::testing
