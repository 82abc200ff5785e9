#include "app/world/board_detector.hpp"

#include <cmath>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace probeless::world {

struct BoardDetector::Impl {
  BoardSpec spec;
  BoardCamera camera;
  cv::Mat K, dist;
  cv::Ptr<cv::aruco::Dictionary> dictionary;
  cv::Ptr<cv::aruco::CharucoBoard> board;  // ChArUco only
  cv::Ptr<cv::aruco::DetectorParameters> params;
  std::vector<cv::Point3f> marker_model;  // ArUco only: its corners, centred
};

namespace {

Pose pose_of(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = R.at<double>(i, j);
  Pose p;
  p.rotation = Eigen::Quaterniond(r).normalized();
  p.translation = Eigen::Vector3d(tvec[0], tvec[1], tvec[2]);
  return p;
}

void reprojection(const std::vector<cv::Point3f>& model, const std::vector<cv::Point2f>& seen,
                  const cv::Vec3d& rvec, const cv::Vec3d& tvec, const cv::Mat& K,
                  const cv::Mat& dist, BoardDetection& d) {
  std::vector<cv::Point2f> projected;
  cv::projectPoints(model, rvec, tvec, K, dist, projected);
  double sum = 0;
  for (std::size_t i = 0; i < projected.size(); ++i) {
    const double e = cv::norm(projected[i] - seen[i]);
    sum += e * e;
    d.max_px = std::max(d.max_px, e);
  }
  d.rms_px = std::sqrt(sum / static_cast<double>(projected.size()));
}

}  // namespace

BoardDetector::BoardDetector(const BoardSpec& board, const BoardCamera& camera)
    : impl_(std::make_unique<Impl>()) {
  if (board.kind == BoardSpec::Kind::Chessboard)
    throw std::invalid_argument(
        "board detection takes a ChArUco board (charuco:...) or an ArUco marker (aruco:...)");
  if (!(camera.K[0] > 0 && camera.K[4] > 0 && camera.K[8] == 1))
    throw std::invalid_argument("board detection: K is not a camera matrix (fx, fy > 0, K33 = 1)");
  const int dictionary = board_dictionary_index(board.dictionary);
  if (dictionary < 0) throw std::invalid_argument("no OpenCV dictionary named " + board.dictionary);
  Impl& m = *impl_;
  m.spec = board;
  m.camera = camera;
  m.K = cv::Mat(3, 3, CV_64F, m.camera.K.data());
  if (!m.camera.distortion.empty())
    m.dist = cv::Mat(1, static_cast<int>(m.camera.distortion.size()), CV_64F,
                     m.camera.distortion.data());
  m.dictionary = cv::aruco::getPredefinedDictionary(dictionary);
  m.params = cv::aruco::DetectorParameters::create();
  if (board.kind == BoardSpec::Kind::Charuco) {
    m.board = cv::aruco::CharucoBoard::create(
        board.cols, board.rows, static_cast<float>(board.square_mm / 1000.0),
        static_cast<float>(board.marker_mm / 1000.0), m.dictionary);
  } else {
    // A lone marker's four corners are all its pose has: refine them to sub-pixel (the
    // ChArUco path refines its chessboard corners instead).
    m.params->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
    const float h = static_cast<float>(board.marker_mm / 2000.0);
    m.marker_model = {{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};  // OpenCV's corner order
  }
}

BoardDetector::~BoardDetector() = default;

Pose BoardDetector::T_board_world() const {
  const BoardSpec& b = impl_->spec;
  if (b.kind == BoardSpec::Kind::Aruco) return Pose::identity();  // x right, y up, z out
  // OpenCV 4.6's ChArUco frame has y down the printed board, so z into it: turned about x.
  Pose p;
  p.translation = Eigen::Vector3d(b.cols * b.square_mm, b.rows * b.square_mm, 0) / 2000.0;
  p.rotation = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX());
  return p;
}

BoardDetection BoardDetector::detect(const ImageRGB8& image) const {
  const Impl& m = *impl_;
  if (m.camera.width > 0 && (image.width() != m.camera.width || image.height() != m.camera.height))
    throw std::invalid_argument("board detection: the image is " + std::to_string(image.width()) +
                                "x" + std::to_string(image.height()) + ", the camera " +
                                std::to_string(m.camera.width) + "x" +
                                std::to_string(m.camera.height));
  const cv::Mat rgb(image.height(), image.width(), CV_8UC3,
                    const_cast<std::uint8_t*>(image.data()));
  cv::Mat gray;
  cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);

  BoardDetection d;
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> marker_ids;
  cv::aruco::detectMarkers(gray, m.dictionary, marker_corners, marker_ids, m.params);
  cv::Vec3d rvec, tvec;
  if (m.spec.kind == BoardSpec::Kind::Aruco) {
    d.board_corners = 4;
    for (std::size_t i = 0; i < marker_ids.size(); ++i) {
      if (marker_ids[i] != m.spec.marker_id) continue;
      d.markers = 1;
      d.corners = 4;
      // IPPE for a square: the planar solution OpenCV's estimatePoseSingleMarkers uses.
      if (!cv::solvePnP(m.marker_model, marker_corners[i], m.K, m.dist, rvec, tvec, false,
                        cv::SOLVEPNP_IPPE_SQUARE))
        return d;
      d.found = true;
      d.T_camera_board = pose_of(rvec, tvec);
      reprojection(m.marker_model, marker_corners[i], rvec, tvec, m.K, m.dist, d);
      return d;
    }
    return d;
  }
  d.board_corners = static_cast<int>(m.board->chessboardCorners.size());
  for (int id : marker_ids)
    if (id < static_cast<int>(m.board->ids.size())) ++d.markers;
  if (d.markers == 0) return d;
  std::vector<cv::Point2f> corners;
  std::vector<int> corner_ids;
  cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, gray, m.board, corners,
                                       corner_ids, m.K, m.dist);
  d.corners = static_cast<int>(corner_ids.size());
  // A pose from fewer than 4 corners is not determined (estimatePoseCharucoBoard refuses too).
  if (d.corners < 4 ||
      !cv::aruco::estimatePoseCharucoBoard(corners, corner_ids, m.board, m.K, m.dist, rvec, tvec))
    return d;
  d.found = true;
  d.T_camera_board = pose_of(rvec, tvec);
  std::vector<cv::Point3f> model;
  for (int id : corner_ids)
    model.push_back(m.board->chessboardCorners[static_cast<std::size_t>(id)]);
  reprojection(model, corners, rvec, tvec, m.K, m.dist, d);
  return d;
}

}  // namespace probeless::world
