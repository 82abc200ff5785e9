#pragma once
// The TUM fr1/rpy frames of ../shared/data for the tracking tests: colour, depth in mm, the
// ground-truth pose, and the ATE after an SE(3) Umeyama alignment (Sturm et al. 2012).
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <vector>

#include "core/camera/pinhole.hpp"
#include "drivers/io/png.hpp"
#include "drivers/replay/tum_source.hpp"
#include "kernels/tracking/dense_tracker.hpp"
#include "support/test_data.hpp"

namespace probeless::testing {

inline constexpr const char* kTumRpy = "rgbd/tum_fr1_rpy";
// The Kinect's rolling-shutter readout, as `eval tracking` gives TUM sequences
// (lab/eval/tracking_dataset.cpp: Kerl et al. ICCV 2015).
inline constexpr double kKinectReadoutS = 0.028;
inline tracking::DenseTrackerParams tum_params() {
  tracking::DenseTrackerParams p;
  p.rolling_shutter_readout_s = kKinectReadoutS;
  return p;
}

// TUM's published fr1 colour camera (https://cvg.cit.tum.de/data/datasets/rgbd-dataset/
// file_formats, "Intrinsic Camera Calibration of the Kinect").
inline PinholeIntrinsics tum_fr1_intrinsics() {
  return {640, 480, 517.3, 516.5, 318.6, 255.3};
}
inline PinholeCamera tum_fr1_camera() {
  return PinholeCamera(tum_fr1_intrinsics(), {0.2624, -0.9531, -0.0054, 0.0026, 1.1633});
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

// One pass of a tracker over the frames: what the TUM tests check and print.
struct TumRun {
  double ate_m = 0;
  int lost = 0, keyframes = 0;
  double min_inlier_fraction = 1;
  double p50_ms = 0, p99_ms = 0, cpu_p50_ms = 0;  // wall and thread CPU time per frame
  double pyramid_ms = 0, align_ms = 0, keyframe_ms = 0, iterations = 0;  // means per frame
  std::vector<Pose> poses;  // identity for frames that were not tracked
};

inline TumRun run_tum(tracking::DenseTracker& tracker, const std::vector<TumFrame>& frames) {
  TumRun run;
  std::vector<Eigen::Vector3d> estimate, truth;
  std::vector<double> ms, cpu_ms;
  for (const auto& f : frames) {
    const auto t0 = std::chrono::steady_clock::now();
    timespec c0{}, c1{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c0);
    const tracking::TrackResult r = tracker.track(f.colour, f.depth_mm, f.timestamp_ns);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c1);
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    cpu_ms.push_back(double(c1.tv_sec - c0.tv_sec) * 1e3 + double(c1.tv_nsec - c0.tv_nsec) * 1e-6);
    run.pyramid_ms += r.pyramid_ms;
    run.align_ms += r.align_ms;
    run.keyframe_ms += r.keyframe_ms;
    run.iterations += r.iterations;
    if (r.state != tracking::TrackingState::Tracking) {
      ++run.lost;
      run.poses.push_back(Pose::identity());
      continue;
    }
    run.poses.push_back(r.T_world_camera);
    run.keyframes += r.new_keyframe;
    run.min_inlier_fraction = std::min(run.min_inlier_fraction, r.inlier_fraction);
    if (!f.truth) continue;
    estimate.push_back(r.T_world_camera.translation);
    truth.push_back(f.truth->translation);
  }
  const double n = double(frames.size());
  run.pyramid_ms /= n;
  run.align_ms /= n;
  run.keyframe_ms /= n;
  run.iterations /= n;
  std::sort(ms.begin(), ms.end());
  std::sort(cpu_ms.begin(), cpu_ms.end());
  run.p50_ms = ms[ms.size() / 2];
  run.p99_ms = ms[ms.size() * 99 / 100];
  run.cpu_p50_ms = cpu_ms[cpu_ms.size() / 2];
  run.ate_m = ate_rmse(estimate, truth);
  return run;
}

inline void print_tum_run(const char* what, std::size_t frames, const TumRun& r) {
  std::printf(
      "[ TUM      ] fr1/rpy, %zu frames, %s: ATE %.4f m, lost %d, keyframes %d, min inliers "
      "%.3f; per frame p50 %.2f ms, p99 %.2f ms, thread CPU p50 %.2f ms; means: pyramid %.2f "
      "ms, align %.2f ms (%.1f iterations), keyframe %.2f ms\n",
      frames, what, r.ate_m, r.lost, r.keyframes, r.min_inlier_fraction, r.p50_ms, r.p99_ms,
      r.cpu_p50_ms, r.pyramid_ms, r.align_ms, r.iterations, r.keyframe_ms);
}

}  // namespace probeless::testing
