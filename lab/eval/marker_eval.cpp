#include "lab/eval/marker_eval.hpp"

#include <cmath>
#include <filesystem>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace probeless::eval {
namespace {

int dictionary_id(const std::string& name) {
  const int id = board_dictionary_index(name);
  if (id < 0) throw std::invalid_argument("no OpenCV dictionary named " + name);
  return id;
}

}  // namespace

BoardCamera read_opencv_camera(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path + ": no such camera file");
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path + ": not an OpenCV FileStorage file (" + e.msg + ")");
  }
  if (!fs.isOpened()) throw std::runtime_error(path + ": cannot open as an OpenCV FileStorage");
  cv::Mat K, d;
  fs["camera_matrix"] >> K;
  fs["distortion_coefficients"] >> d;
  if (K.rows != 3 || K.cols != 3) throw std::runtime_error(path + ": camera_matrix is not 3x3");
  if (d.total() < 4 || d.total() > 14)
    throw std::runtime_error(path + ": distortion_coefficients must have 4 to 14 terms");
  BoardCamera c;
  K.convertTo(K, CV_64F);
  d.convertTo(d, CV_64F);
  for (int i = 0; i < 9; ++i) c.K[static_cast<std::size_t>(i)] = K.at<double>(i / 3, i % 3);
  c.distortion.assign(d.begin<double>(), d.end<double>());
  if (!fs["image_width"].empty()) fs["image_width"] >> c.width;
  if (!fs["image_height"].empty()) fs["image_height"] >> c.height;
  return c;
}

BoardPose find_board_pose(const std::string& image_path, const BoardCamera& camera,
                          const BoardSpec& spec) {
  if (spec.kind != BoardSpec::Kind::Charuco)
    throw std::invalid_argument("eval marker takes a ChArUco board (charuco:...)");
  const cv::Mat image = cv::imread(image_path, cv::IMREAD_COLOR);
  if (image.empty()) throw std::runtime_error(image_path + ": cannot read the image");
  if (camera.width > 0 && (image.cols != camera.width || image.rows != camera.height))
    throw std::runtime_error(image_path + ": the image is " + std::to_string(image.cols) + "x" +
                             std::to_string(image.rows) + " but the camera was calibrated at " +
                             std::to_string(camera.width) + "x" + std::to_string(camera.height));

  const auto dictionary = cv::aruco::getPredefinedDictionary(dictionary_id(spec.dictionary));
  const auto board = cv::aruco::CharucoBoard::create(
      spec.cols, spec.rows, static_cast<float>(spec.square_mm / 1000.0),
      static_cast<float>(spec.marker_mm / 1000.0), dictionary);
  const cv::Mat K(3, 3, CV_64F, const_cast<double*>(camera.K.data()));
  const cv::Mat dist(1, static_cast<int>(camera.distortion.size()), CV_64F,
                     const_cast<double*>(camera.distortion.data()));

  BoardPose pose;
  pose.board_corners = static_cast<int>(board->chessboardCorners.size());
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> marker_ids;
  cv::aruco::detectMarkers(image, board->dictionary, marker_corners, marker_ids);
  pose.markers = static_cast<int>(marker_ids.size());
  if (marker_ids.empty()) return pose;
  std::vector<cv::Point2f> corners;
  std::vector<int> corner_ids;
  cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, image, board, corners,
                                       corner_ids, K, dist);
  pose.corners = static_cast<int>(corner_ids.size());
  cv::Vec3d rvec, tvec;
  // A pose from fewer than 4 corners is not determined (estimatePoseCharucoBoard refuses too).
  if (pose.corners < 4 ||
      !cv::aruco::estimatePoseCharucoBoard(corners, corner_ids, board, K, dist, rvec, tvec))
    return pose;
  pose.found = true;
  for (int i = 0; i < 3; ++i) {
    pose.t_m[static_cast<std::size_t>(i)] = tvec[i];
    pose.rvec[static_cast<std::size_t>(i)] = rvec[i];
  }
  pose.rotation_deg = cv::norm(rvec) * 180.0 / CV_PI;

  std::vector<cv::Point3f> model;
  for (int id : corner_ids) model.push_back(board->chessboardCorners[static_cast<std::size_t>(id)]);
  std::vector<cv::Point2f> projected;
  cv::projectPoints(model, rvec, tvec, K, dist, projected);
  double sum = 0;
  for (std::size_t i = 0; i < projected.size(); ++i) {
    const double e = cv::norm(projected[i] - corners[i]);
    sum += e * e;
    pose.max_px = std::max(pose.max_px, e);
  }
  pose.rms_px = std::sqrt(sum / static_cast<double>(projected.size()));
  return pose;
}

}  // namespace probeless::eval
