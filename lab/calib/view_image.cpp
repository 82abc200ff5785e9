#include "lab/calib/view_image.hpp"

#include <fmt/format.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace probeless::calib {

void write_view_png(const std::filesystem::path& path, const ImageGray8& image,
                    const BoardView& view, const std::vector<Eigen::Vector2d>& reprojected,
                    double rms_px) {
  const cv::Mat gray(image.height(), image.width(), CV_8UC1,
                     const_cast<std::uint8_t*>(image.data()));
  cv::Mat canvas;
  cv::cvtColor(gray, canvas, cv::COLOR_GRAY2BGR);
  // Marks scale with the image so that they stay visible on a 1296-px fisheye and small on VGA.
  const int mark = std::max(3, std::max(image.width(), image.height()) / 160);
  const auto at = [](const Eigen::Vector2d& p) { return cv::Point2d(p.x(), p.y()); };
  for (const auto& p : view.pixels)
    cv::circle(canvas, at(p), mark, cv::Scalar(0, 200, 0), 1, cv::LINE_AA);
  for (const auto& p : reprojected)
    cv::drawMarker(canvas, at(p), cv::Scalar(0, 0, 255), cv::MARKER_CROSS, 2 * mark, 1,
                   cv::LINE_AA);
  const std::string label =
      fmt::format("{}: {} corners, RMS {:.3f} px", view.name, view.pixels.size(), rms_px);
  cv::putText(canvas, label, cv::Point(8, 8 + 2 * mark), cv::FONT_HERSHEY_SIMPLEX, 0.4 * mark / 3.0,
              cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), canvas);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path.string() + ": cannot write (" + e.msg + ")");
  }
  if (!ok) throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace probeless::calib
