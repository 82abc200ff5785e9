#include "lab/calib/board_detector.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <stdexcept>

namespace probeless::calib {

struct BoardDetector::Impl {
  cv::Ptr<cv::aruco::CharucoBoard> charuco;  // null for a chessboard
};

namespace {

cv::Mat wrap(const ImageGray8& image) {
  return cv::Mat(image.height(), image.width(), CV_8UC1, const_cast<std::uint8_t*>(image.data()));
}

// Refines corners with cornerSubPix. The window must hold nothing but the corner's two edges:
// it stays within `clear_fraction` of the spacing of the closest two corners (half of it for
// a chessboard: never up to the next corner, as at a fisheye's rim; for ChArUco the white
// border between a corner and the markers beside it), and at most OpenCV's usual 11.
void refine_corners(const cv::Mat& gray, std::vector<cv::Point2f>& corners, double clear_fraction) {
  double spacing = 1e9;
  for (std::size_t i = 0; i < corners.size(); ++i)
    for (std::size_t j = i + 1; j < corners.size(); ++j)
      spacing = std::min(spacing, static_cast<double>(cv::norm(corners[j] - corners[i])));
  const int half = std::clamp(static_cast<int>(clear_fraction * spacing) - 1, 2, 11);
  cv::cornerSubPix(gray, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
}

// OpenCV 4.6's interpolateCornersCharuco leaves its corners about where the markers' contours
// put them: measured against their true projections on the sim's board, +0.5 px in x and in
// y in both cameras at every angle off the axis (0.70 px RMS; tests/integration/calibrate_sim
// corner_bias_test.cpp), which cost the rig extrinsics 0.18 deg (docs/calibration.md "Checked
// on the sim"). Its refinement passes the window it computed per corner as cornerSubPix's dead
// zone and its default size as the window (aruco/src/charuco.cpp,
// _selectAndRefineChessboardCorners). So each corner is refined again as OpenCV meant, with
// its aruco defaults (11 x 11 window, 30 iterations, 0.1 px), the window kept inside the white
// border between the corner and the nearest marker corners: that border is a square of half
// their distance / sqrt 2 in board units, so half their distance holds it at any rotation.
// Measured: the same corners to 0.08 px RMS (colour), 0.07-0.19 px (fisheye, rim last), means
// under 0.04 px. A larger window (up to 10 px) or a tighter stop moved the four tutorial
// views' fx or cy by 2-4 %: four nearly parallel views (docs/calibration.md "Results").
void refine_charuco_corners(const cv::Mat& gray,
                            const std::vector<std::vector<cv::Point2f>>& marker_corners,
                            std::vector<cv::Point2f>& corners) {
  const auto defaults = cv::aruco::DetectorParameters::create();
  const cv::TermCriteria stop(cv::TermCriteria::EPS + cv::TermCriteria::COUNT,
                              defaults->cornerRefinementMaxIterations,
                              defaults->cornerRefinementMinAccuracy);
  for (cv::Point2f& c : corners) {
    double nearest = 1e9;
    for (const auto& marker : marker_corners)
      for (const cv::Point2f& m : marker)
        nearest = std::min(nearest, static_cast<double>(cv::norm(m - c)));
    const int half = std::clamp(static_cast<int>(0.5 * nearest), 2,
                                std::max(2, defaults->cornerRefinementWinSize));
    std::vector<cv::Point2f> one{c};
    cv::cornerSubPix(gray, one, cv::Size(half, half), cv::Size(-1, -1), stop);
    c = one[0];
  }
}

std::optional<std::vector<cv::Point2f>> find_chessboard(const cv::Mat& gray, int cols, int rows) {
  std::vector<cv::Point2f> corners;
  const cv::Size pattern(cols, rows);
  if (cv::findChessboardCorners(gray, pattern, corners,
                                cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE)) {
    refine_corners(gray, corners, 0.5);
    return corners;
  }
  // The sector-based detector copes better with strong blur and fisheye bending, and its
  // corners are already refined (Duda & Frese 2018).
  if (cv::findChessboardCornersSB(gray, pattern, corners,
                                  cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY))
    return corners;
  return std::nullopt;
}

cv::Ptr<cv::aruco::CharucoBoard> make_charuco(const BoardSpec& spec) {
  const int dict = board_dictionary_index(spec.dictionary);
  if (dict < 0) throw std::invalid_argument("no OpenCV dictionary named " + spec.dictionary);
  return cv::aruco::CharucoBoard::create(
      spec.cols, spec.rows, static_cast<float>(spec.square_mm / 1000.0),
      static_cast<float>(spec.marker_mm / 1000.0), cv::aruco::getPredefinedDictionary(dict));
}

}  // namespace

BoardDetector::BoardDetector(const BoardSpec& spec) : spec_(spec), impl_(std::make_unique<Impl>()) {
  if (spec.kind == BoardSpec::Kind::Charuco) impl_->charuco = make_charuco(spec);
}

BoardDetector::~BoardDetector() = default;

int BoardDetector::corner_count() const {
  return spec_.kind == BoardSpec::Kind::Charuco ? (spec_.cols - 1) * (spec_.rows - 1)
                                                : spec_.cols * spec_.rows;
}

std::optional<BoardView> BoardDetector::detect(const ImageGray8& image,
                                               const std::string& name) const {
  const cv::Mat gray = wrap(image);
  BoardView view;
  view.name = name;
  view.width = image.width();
  view.height = image.height();

  if (!impl_->charuco) {
    const auto corners = find_chessboard(gray, spec_.cols, spec_.rows);
    if (!corners) return std::nullopt;
    const double square = spec_.square_mm / 1000.0;
    for (int i = 0; i < static_cast<int>(corners->size()); ++i) {
      const cv::Point2f& c = (*corners)[static_cast<std::size_t>(i)];
      view.pixels.emplace_back(c.x, c.y);
      view.points.emplace_back((i % spec_.cols) * square, (i / spec_.cols) * square, 0.0);
      view.ids.push_back(i);
    }
    return view;
  }

  const auto& board = impl_->charuco;
  std::vector<std::vector<cv::Point2f>> marker_corners, rejected;
  std::vector<int> marker_ids;
  cv::aruco::detectMarkers(gray, board->dictionary, marker_corners, marker_ids,
                           cv::aruco::DetectorParameters::create(), rejected);
  if (marker_ids.empty()) return std::nullopt;
  // Markers missed at first are looked for where the board says they must be.
  cv::aruco::refineDetectedMarkers(gray, board, marker_corners, marker_ids, rejected);
  std::vector<cv::Point2f> corners;
  std::vector<int> ids;
  cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, gray, board, corners, ids);
  refine_charuco_corners(gray, marker_corners, corners);
  if (static_cast<int>(ids.size()) < kMinCharucoCorners) return std::nullopt;
  std::set<int> columns, rows;
  for (int id : ids) {
    columns.insert(id % (spec_.cols - 1));
    rows.insert(id / (spec_.cols - 1));
  }
  if (columns.size() < 2 || rows.size() < 2) return std::nullopt;  // one line: no homography
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const cv::Point3f& p = board->chessboardCorners[static_cast<std::size_t>(ids[i])];
    view.pixels.emplace_back(corners[i].x, corners[i].y);
    view.points.emplace_back(p.x, p.y, p.z);
    view.ids.push_back(ids[i]);
  }
  return view;
}

ImageGray8 board_image(const BoardSpec& spec, int pixels_per_square) {
  if (pixels_per_square < 4) throw std::invalid_argument("board_image: at least 4 px a square");
  // A chessboard's inner corners are at multiples of the square from the first one, which is
  // one square in from the pattern's edge; a ChArUco board's frame starts at its corner.
  const int squares_x = spec.kind == BoardSpec::Kind::Charuco ? spec.cols : spec.cols + 1;
  const int squares_y = spec.kind == BoardSpec::Kind::Charuco ? spec.rows : spec.rows + 1;
  cv::Mat drawn;
  if (spec.kind == BoardSpec::Kind::Charuco) {
    make_charuco(spec)->draw(cv::Size(squares_x * pixels_per_square, squares_y * pixels_per_square),
                             drawn, 0, 1);
  } else {
    drawn = cv::Mat(squares_y * pixels_per_square, squares_x * pixels_per_square, CV_8UC1);
    for (int y = 0; y < drawn.rows; ++y)
      for (int x = 0; x < drawn.cols; ++x)
        drawn.at<std::uint8_t>(y, x) =
            ((x / pixels_per_square + y / pixels_per_square) % 2 == 0) ? 0 : 255;
  }
  ImageGray8 out(drawn.cols, drawn.rows);
  for (int y = 0; y < drawn.rows; ++y)
    std::copy_n(drawn.ptr<std::uint8_t>(y), drawn.cols, out.row(y));
  return out;
}

ImageGray8 read_gray_image(const std::filesystem::path& path) {
  cv::Mat m;
  try {
    m = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path.string() + ": cannot read the image (" + e.msg + ")");
  }
  if (m.empty()) throw std::runtime_error(path.string() + ": cannot read the image");
  ImageGray8 out(m.cols, m.rows);
  for (int y = 0; y < m.rows; ++y) std::copy_n(m.ptr<std::uint8_t>(y), m.cols, out.row(y));
  return out;
}

ImageGray8 to_gray(const ImageRGB8& colour) {
  ImageGray8 out(colour.width(), colour.height());
  const cv::Mat rgb(colour.height(), colour.width(), CV_8UC3,
                    const_cast<std::uint8_t*>(colour.data()));
  cv::Mat gray(out.height(), out.width(), CV_8UC1, out.data());
  cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);
  return out;
}

}  // namespace probeless::calib
