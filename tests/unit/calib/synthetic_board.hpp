#pragma once
// Board views with known truth for the calibration tests: a chessboard held in front of and
// above a rig whose fisheye looks up, its corners projected through core's camera models.
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "core/camera/camera_model.hpp"
#include "core/pose.hpp"
#include "lab/calib/board_detector.hpp"

namespace probeless::calib::testing {

inline constexpr int kCols = 9, kRows = 6;  // inner corners
inline constexpr double kSquare = 0.04;     // metres

inline std::vector<Eigen::Vector3d> board_corners() {
  std::vector<Eigen::Vector3d> points;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kCols; ++c) points.emplace_back(c * kSquare, r * kSquare, 0.0);
  return points;
}

inline Eigen::Quaterniond rotation_deg(double x, double y, double z) {
  const double k = std::numbers::pi / 180.0;
  return Eigen::Quaterniond(Eigen::AngleAxisd(z * k, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(y * k, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(x * k, Eigen::Vector3d::UnitX()));
}

// The board's corners through `camera` at `T_camera_board`, with Gaussian pixel noise; empty
// when any corner is not seen (outside the model's domain or the image).
inline std::vector<Eigen::Vector2d> project_board(const CameraModel& camera,
                                                  const Pose& T_camera_board, double noise_px,
                                                  std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<Eigen::Vector2d> pixels;
  for (const auto& p : board_corners()) {
    const Eigen::Vector3d q = T_camera_board * p;
    const auto px = camera.project(q);
    if (!px || !camera.in_image(*px) || q.z() <= 0.05) return {};
    pixels.push_back(*px + Eigen::Vector2d(noise(rng), noise(rng)));
  }
  return pixels;
}

inline BoardView board_view(const std::string& name, const CameraModel& camera,
                            std::vector<Eigen::Vector2d> pixels) {
  BoardView v;
  v.name = name;
  v.width = camera.width();
  v.height = camera.height();
  v.pixels = std::move(pixels);
  v.points = board_corners();
  for (int i = 0; i < kCols * kRows; ++i) v.ids.push_back(i);
  return v;
}

// A board pose in the camera frame: centre `centre`, its face turned towards the camera and
// then tilted by (tilt_x, tilt_y) degrees and spun by `spin` degrees about its normal.
inline Pose board_pose(const Eigen::Vector3d& centre, double tilt_x, double tilt_y, double spin) {
  Pose p;
  p.rotation = rotation_deg(tilt_x, tilt_y, spin);
  const Eigen::Vector3d half((kCols - 1) * kSquare / 2, (kRows - 1) * kSquare / 2, 0);
  p.translation = centre - p.rotation * half;
  return p;
}

}  // namespace probeless::calib::testing
