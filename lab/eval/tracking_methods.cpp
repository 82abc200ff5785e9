#include "lab/eval/tracking_methods.hpp"

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd.hpp>
#include <sstream>
#include <stdexcept>

#include "kernels/tracking/dense_tracker.hpp"

namespace probeless::eval {
namespace {

class DenseMethod final : public TrackingMethod {
 public:
  DenseMethod(std::string name, ComputeContext* ctx, const PinholeIntrinsics& camera,
              const TrackingDepthRange& range, double rolling_shutter_readout_s)
      : name_(std::move(name)), tracker_(ctx, camera, params(range, rolling_shutter_readout_s)) {}
  const std::string& name() const override { return name_; }
  TrackingStep track(const ImageRGB8& colour, const DepthImage& depth_mm,
                     TimestampNs timestamp_ns) override {
    const tracking::TrackResult r = tracker_.track(colour, depth_mm, timestamp_ns);
    if (r.state != tracking::TrackingState::Tracking) return {last_, true, -1};
    last_ = r.T_world_camera;
    return {last_, false, r.keyframe_id};
  }
  void reset() override {
    tracker_.reset();
    last_ = Pose::identity();
  }

 private:
  static tracking::DenseTrackerParams params(const TrackingDepthRange& range,
                                             double rolling_shutter_readout_s) {
    tracking::DenseTrackerParams p;
    p.min_depth_m = range.min_m;
    p.max_depth_m = range.max_m;
    p.rolling_shutter_readout_s = rolling_shutter_readout_s;
    return p;
  }
  std::string name_;
  tracking::DenseTracker tracker_;
  Pose last_;
};

// OpenCV's odometry frame to frame: each new frame is the source, the previous one the
// destination, so Rt = T_previous_current (dst_p = Rt src_p) chains onto the last pose, as
// OpenCV's own samples/odometry_evaluation.cpp does. The previous frame keeps its cache
// (pyramids, normals), so no frame is prepared twice.
class OpenCvMethod final : public TrackingMethod {
 public:
  OpenCvMethod(std::string name, cv::Ptr<cv::rgbd::Odometry> odometry)
      : name_(std::move(name)), odometry_(std::move(odometry)) {}
  const std::string& name() const override { return name_; }
  TrackingStep track(const ImageRGB8& colour, const DepthImage& depth_mm, TimestampNs) override {
    const cv::Mat rgb(colour.height(), colour.width(), CV_8UC3,
                      const_cast<std::uint8_t*>(colour.data()));
    const cv::Mat mm(depth_mm.height(), depth_mm.width(), CV_16UC1,
                     const_cast<std::uint16_t*>(depth_mm.data()));
    cv::Mat gray, metres;
    cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);
    mm.convertTo(metres, CV_32FC1, 1e-3);  // 0 (unknown) stays 0, outside OpenCV's range
    cv::Ptr<cv::rgbd::OdometryFrame> frame = cv::rgbd::OdometryFrame::create(gray, metres);
    if (!previous_) {
      previous_ = frame;
      return {pose_, false};
    }
    cv::Mat rt;
    bool ok = false;
    try {
      ok = odometry_->compute(frame, previous_, rt);
    } catch (const cv::Exception&) {
      ok = false;  // degenerate input (too few valid pixels): a lost frame, as compute() false
    }
    previous_ = frame;
    if (!ok) return {pose_, true};
    Eigen::Matrix4d m;
    cv::cv2eigen(rt, m);
    pose_ = pose_ * Pose::from_matrix(m);
    return {pose_, false};
  }
  void reset() override {
    previous_.release();
    pose_ = Pose::identity();
  }

 private:
  std::string name_;
  cv::Ptr<cv::rgbd::Odometry> odometry_;
  cv::Ptr<cv::rgbd::OdometryFrame> previous_;
  Pose pose_;
};

cv::Mat camera_matrix(const PinholeIntrinsics& k) {
  return (cv::Mat_<float>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
}

}  // namespace

const std::vector<std::string>& tracking_method_names() {
  static const std::vector<std::string> names{"dense", "dense_cpu", "opencv_rgbd", "opencv_icp",
                                              "opencv_rgbdicp"};
  return names;
}

std::unique_ptr<TrackingMethod> make_tracking_method(const std::string& name,
                                                     const PinholeIntrinsics& camera,
                                                     const TrackingDepthRange& range,
                                                     ComputeContext* ctx,
                                                     double rolling_shutter_readout_s) {
  if (name == "dense") {
    if (!ctx) throw std::invalid_argument("tracking method dense needs an OpenCL context");
    return std::make_unique<DenseMethod>(name, ctx, camera, range, rolling_shutter_readout_s);
  }
  if (name == "dense_cpu")
    return std::make_unique<DenseMethod>(name, nullptr, camera, range, rolling_shutter_readout_s);
  // OpenCV's defaults for everything but the depth range (max depth difference 0.07 m,
  // 7% of the points, its own iteration counts and gradient thresholds).
  const cv::Mat k = camera_matrix(camera);
  cv::Ptr<cv::rgbd::Odometry> odometry;
  if (name == "opencv_rgbd")
    odometry = cv::rgbd::RgbdOdometry::create(k, range.min_m, range.max_m);
  else if (name == "opencv_icp")
    odometry = cv::rgbd::ICPOdometry::create(k, range.min_m, range.max_m);
  else if (name == "opencv_rgbdicp")
    odometry = cv::rgbd::RgbdICPOdometry::create(k, range.min_m, range.max_m);
  else
    throw std::invalid_argument("unknown tracking method '" + name + "'");
  return std::make_unique<OpenCvMethod>(name, std::move(odometry));
}

std::vector<std::string> parse_tracking_methods(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    if (name.empty()) continue;
    bool known = false;
    for (const auto& n : tracking_method_names()) known = known || n == name;
    if (!known) {
      std::string all;
      for (const auto& n : tracking_method_names()) all += (all.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown tracking method '" + name + "' (known: " + all + ")");
    }
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
  }
  if (out.empty()) throw std::invalid_argument("no tracking method named");
  return out;
}

}  // namespace probeless::eval
