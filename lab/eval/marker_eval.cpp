#include "lab/eval/marker_eval.hpp"

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace probeless::eval {
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
  const cv::Mat bgr = cv::imread(image_path, cv::IMREAD_COLOR);
  if (bgr.empty()) throw std::runtime_error(image_path + ": cannot read the image");
  if (camera.width > 0 && (bgr.cols != camera.width || bgr.rows != camera.height))
    throw std::runtime_error(image_path + ": the image is " + std::to_string(bgr.cols) + "x" +
                             std::to_string(bgr.rows) + " but the camera was calibrated at " +
                             std::to_string(camera.width) + "x" + std::to_string(camera.height));
  ImageRGB8 image(bgr.cols, bgr.rows);
  cv::Mat rgb(bgr.rows, bgr.cols, CV_8UC3, image.data());
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);

  const world::BoardDetection d = world::BoardDetector(spec, camera).detect(image);
  BoardPose pose;
  pose.found = d.found;
  pose.markers = d.markers;
  pose.corners = d.corners;
  pose.board_corners = d.board_corners;
  if (!d.found) return pose;
  const Eigen::AngleAxisd r(d.T_camera_board.rotation);
  for (int i = 0; i < 3; ++i) {
    pose.t_m[static_cast<std::size_t>(i)] = d.T_camera_board.translation[i];
    pose.rvec[static_cast<std::size_t>(i)] = r.axis()[i] * r.angle();
  }
  pose.rotation_deg = r.angle() * 180.0 / CV_PI;
  pose.rms_px = d.rms_px;
  pose.max_px = d.max_px;
  return pose;
}

}  // namespace probeless::eval
