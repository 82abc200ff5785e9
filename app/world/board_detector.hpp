#pragma once
// Finding a ChArUco board or one ArUco marker in a colour image and its pose, with OpenCV's
// aruco module (Debian's OpenCV 4.6 contrib): what `[world] anchor = "marker"` rests on, and
// `probeless eval marker` measures on real photos (lab/eval/marker_eval.*). OpenCV stays in
// the .cpp: this header is the appliance's whole view of it.
#include <array>
#include <memory>
#include <vector>

#include "core/board_spec.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"

namespace probeless::world {

struct BoardCamera {
  std::array<double, 9> K{};       // row-major 3x3
  std::vector<double> distortion;  // OpenCV's order: k1 k2 p1 p2 [k3 ...]; empty: none
  int width = 0, height = 0;       // 0: not known
};

struct BoardDetection {
  bool found = false;     // a pose was estimated
  int markers = 0;        // ArUco markers of the target detected
  int corners = 0;        // corners the pose rests on (ChArUco: interpolated chessboard corners)
  int board_corners = 0;  // corners the target has
  // The target in the camera frame, in OpenCV's target frame (the object points of OpenCV
  // 4.6's CharucoBoard: origin at a corner of the board, x along its columns, y along its
  // rows; a marker's origin at its centre, x right, y up), z out of the printed face.
  Pose T_camera_board;
  double rms_px = 0;  // corner reprojection error of that pose
  double max_px = 0;
};

class BoardDetector {
 public:
  // Throws std::invalid_argument for a chessboard (its pose is ambiguous) or a camera whose K
  // is not a camera matrix.
  BoardDetector(const BoardSpec& board, const BoardCamera& camera);
  ~BoardDetector();
  BoardDetector(const BoardDetector&) = delete;
  BoardDetector& operator=(const BoardDetector&) = delete;

  // Throws std::invalid_argument when the image is not the camera's size.
  BoardDetection detect(const ImageRGB8& image) const;
  // The world the target anchors, in its target frame: origin at the middle of the board (of
  // the marker: its centre), z out of the printed face, x along its columns (docs/tracking.md
  // "World anchoring").
  Pose T_board_world() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace probeless::world
