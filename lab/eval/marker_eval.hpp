#pragma once
// `probeless eval marker` (issue #17, docs/tracking.md "Boards"): finds a ChArUco board in one
// photo with OpenCV's aruco module (Debian's OpenCV 4.6 contrib), estimates its pose with the
// camera's intrinsics, and measures how well that pose explains the detected corners: the RMS
// distance between each interpolated chessboard corner and the board model's corner
// projected with the pose, in pixels. A check on real photos of what world anchoring with a
// board will rest on.
#include <array>
#include <string>
#include <vector>

#include "app/world/board_detector.hpp"
#include "core/board_spec.hpp"

namespace probeless::eval {

// The service's detector (app/world/board_detector.hpp) runs the photo: what is measured here
// is what world anchoring does.
using world::BoardCamera;

// An OpenCV FileStorage file with `camera_matrix` and `distortion_coefficients` (what
// OpenCV's calibration samples write). Throws std::runtime_error naming the file and the key.
BoardCamera read_opencv_camera(const std::string& path);

struct BoardPose {
  bool found = false;            // a pose was estimated (enough corners)
  int markers = 0;               // ArUco markers detected
  int corners = 0;               // chessboard corners interpolated
  int board_corners = 0;         // corners the board has
  std::array<double, 3> t_m{};   // board origin in the camera frame, metres
  std::array<double, 3> rvec{};  // Rodrigues rotation board -> camera
  double rotation_deg = 0;       // |rvec| in degrees
  double rms_px = 0;             // corner reprojection RMS
  double max_px = 0;
};

// Throws std::invalid_argument for a board that is not ChArUco, std::runtime_error for an
// image that cannot be read.
BoardPose find_board_pose(const std::string& image_path, const BoardCamera& camera,
                          const BoardSpec& board);

}  // namespace probeless::eval
