#pragma once
// Finds a calibration board (core/board_spec.hpp) in one image with OpenCV (issue #18 item 1,
// docs/calibration.md): ChArUco boards through the aruco module (markers, then the chessboard
// corners between them interpolated and refined), chessboards through calib3d, refined with
// cornerSubPix. The result is plain data (no OpenCV type) so that the solvers and the tests
// can use it without OpenCV.
//
// eval marker (lab/eval/marker_eval.hpp) finds the board with known intrinsics to measure a
// pose; calibration has no intrinsics yet, so the corners are interpolated through the
// markers' local homographies instead.
#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/board_spec.hpp"
#include "core/image.hpp"

namespace probeless::calib {

// The board's corners seen in one image.
struct BoardView {
  std::string name;  // the image's file name (or frame) for messages and reports
  int width = 0, height = 0;
  std::vector<Eigen::Vector2d> pixels;  // detected corners, OpenCV pixel convention
  std::vector<Eigen::Vector3d> points;  // the same corners on the board (metres, z = 0)
  std::vector<int> ids;                 // corner ids (row-major over the board's corners)
};

class BoardDetector {
 public:
  // Throws std::invalid_argument for a ChArUco dictionary OpenCV does not know.
  explicit BoardDetector(const BoardSpec& spec);
  ~BoardDetector();
  BoardDetector(const BoardDetector&) = delete;
  BoardDetector& operator=(const BoardDetector&) = delete;

  // nullopt when the board is not found: for a chessboard, not every inner corner; for a
  // ChArUco board, fewer than kMinCharucoCorners corners or all of them on one line.
  std::optional<BoardView> detect(const ImageGray8& image, const std::string& name) const;
  int corner_count() const;  // inner corners the board has
  const BoardSpec& spec() const { return spec_; }

  // A partial ChArUco view needs enough corners off one line for its homography and pose.
  static constexpr int kMinCharucoCorners = 6;

 private:
  struct Impl;
  BoardSpec spec_;
  std::unique_ptr<Impl> impl_;
};

// The board as printed, `pixels_per_square` pixels to a square, without margin (leave a white
// one around it). Pixel (u, v) shows the board point (s (u + 0.5) / n - o, s (v + 0.5) / n - o)
// of BoardView::points' frame, with s the square side, n = pixels_per_square and o = s for a
// chessboard (its first inner corner is one square in) and 0 for a ChArUco board. For
// printing, and for rendering synthetic views in the tests.
ImageGray8 board_image(const BoardSpec& spec, int pixels_per_square);

// Any image OpenCV reads (JPEG, PNG, ...) as 8-bit gray. Throws std::runtime_error naming the
// file when it cannot be read.
ImageGray8 read_gray_image(const std::filesystem::path& path);
// Rec. 601 luma, as OpenCV's cvtColor does.
ImageGray8 to_gray(const ImageRGB8& colour);

}  // namespace probeless::calib
