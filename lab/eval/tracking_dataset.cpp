#include "lab/eval/tracking_dataset.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <stdexcept>

#include "drivers/io/png.hpp"
#include "drivers/replay/tum_source.hpp"
#include "drivers/sim/sim_rig.hpp"

namespace probeless::eval {
namespace fs = std::filesystem;
namespace {

// Undistorts colour (bilinear) and depth (nearest: interpolating across a depth edge would
// invent surfaces) onto the same K without distortion, maps computed once.
class Undistorter {
 public:
  Undistorter(const PinholeIntrinsics& k, const BrownDistortion& d) {
    if (d.is_zero()) return;
    const cv::Matx33d cam(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    const cv::Vec<double, 5> dist(d.k1, d.k2, d.p1, d.p2, d.k3);
    cv::initUndistortRectifyMap(cam, dist, cv::Matx33d::eye(), cam, cv::Size(k.width, k.height),
                                CV_32FC1, map_x_, map_y_);
  }
  bool active() const { return !map_x_.empty(); }
  void apply(TrackingFrame& f) const {
    if (!active()) return;
    if (f.colour.width() != map_x_.cols || f.colour.height() != map_x_.rows)
      throw std::runtime_error(fmt::format("frame is {}x{} but the camera is {}x{}",
                                           f.colour.width(), f.colour.height(), map_x_.cols,
                                           map_x_.rows));
    ImageRGB8 colour(f.colour.width(), f.colour.height());
    DepthImage depth(f.depth_mm.width(), f.depth_mm.height());
    cv::remap(cv::Mat(f.colour.height(), f.colour.width(), CV_8UC3, f.colour.data()),
              cv::Mat(colour.height(), colour.width(), CV_8UC3, colour.data()), map_x_, map_y_,
              cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    cv::remap(cv::Mat(f.depth_mm.height(), f.depth_mm.width(), CV_16UC1, f.depth_mm.data()),
              cv::Mat(depth.height(), depth.width(), CV_16UC1, depth.data()), map_x_, map_y_,
              cv::INTER_NEAREST, cv::BORDER_CONSTANT);
    f.colour = std::move(colour);
    f.depth_mm = std::move(depth);
  }

 private:
  cv::Mat map_x_, map_y_;
};

std::string describe(const PinholeIntrinsics& k, const BrownDistortion& d) {
  return fmt::format("fx {} fy {} cx {} cy {}, {}", k.fx, k.fy, k.cx, k.cy,
                     d.is_zero() ? std::string("no distortion")
                                 : fmt::format("distortion {} {} {} {} {} (undistorted)", d.k1,
                                               d.k2, d.p1, d.p2, d.k3));
}

class TumTracking final : public TrackingSequence {
 public:
  TumTracking(const fs::path& dir, const fs::path& calibration, int max_frames)
      : seq_(replay::open_tum_sequence(dir, calibration)), max_frames_(max_frames) {
    std::string folder = dir.lexically_normal().filename().string();
    if (folder.empty()) folder = dir.lexically_normal().parent_path().filename().string();
    name_ = folder;
    PinholeIntrinsics k = seq_.calibration.rgb.intrinsics();
    BrownDistortion d = seq_.calibration.rgb.distortion();
    std::string source = "calibration " + calibration.string();
    if (calibration.empty()) {
      source = "TUM default";
      if (const auto published = tum_camera_for_folder(folder)) {
        k = published->intrinsics;
        d = published->distortion;
        source = fmt::format("TUM fr{} published", published->sensor);
      }
    }
    camera_ = k;
    description_ = source + ": " + describe(k, d);
    undistort_ = std::make_unique<Undistorter>(k, d);
    T_rig_camera_ = seq_.calibration.T_rig_rgb;
    // The world is anchored at the first frame with ground truth: frames before the
    // trajectory starts are skipped.
    while (next_ < seq_.frames.size() && !seq_.frames[next_].rig_pose) ++next_;
    if (next_ == seq_.frames.size())
      throw std::invalid_argument(
          fs::exists(dir / "groundtruth.txt")
              ? fmt::format("{}: no frame lies within groundtruth.txt's time span", dir.string())
              : fmt::format("{}: no groundtruth.txt: eval tracking needs the ground truth",
                            dir.string()));
  }
  const std::string& name() const override { return name_; }
  const PinholeIntrinsics& camera() const override { return camera_; }
  // Every TUM sequence is a Kinect v1 or Xtion, rolling-shutter CMOS sensors; TUM publishes
  // no readout time. 28 ms is the one Kerl, Stueckler & Cremers (ICCV 2015) give their
  // simulated rolling-shutter RGB-D camera, under the 33 ms frame interval at 30 Hz.
  double rolling_shutter_readout_s() const override { return 0.028; }
  const std::string& camera_description() const override { return description_; }
  std::optional<TrackingFrame> next() override {
    if (next_ >= seq_.frames.size() || (max_frames_ > 0 && delivered_ >= max_frames_))
      return std::nullopt;
    const auto& f = seq_.frames[next_++];
    TrackingFrame out;
    out.timestamp_ns = f.timestamp_ns;
    out.colour = read_png_rgb8(seq_.dir / f.colour);
    out.depth_mm = replay::tum_depth_to_mm(read_png_depth16(seq_.dir / f.depth));
    if (out.colour.width() != camera_.width || out.colour.height() != camera_.height ||
        out.depth_mm.width() != camera_.width || out.depth_mm.height() != camera_.height)
      throw std::runtime_error(fmt::format("{}: colour {}x{}, depth {}x{}, camera {}x{}",
                                           (seq_.dir / f.colour).string(), out.colour.width(),
                                           out.colour.height(), out.depth_mm.width(),
                                           out.depth_mm.height(), camera_.width, camera_.height));
    if (f.rig_pose) out.T_world_camera = *f.rig_pose * T_rig_camera_;
    undistort_->apply(out);
    ++delivered_;
    return out;
  }

 private:
  replay::TumSequence seq_;
  int max_frames_;
  std::string name_, description_;
  PinholeIntrinsics camera_;
  std::unique_ptr<Undistorter> undistort_;
  Pose T_rig_camera_;
  std::size_t next_ = 0;
  int delivered_ = 0;
};

// The sim's rig on its scripted trajectory (orbit by default: 1.7 m around the table, a
// revolution a minute), rendered as fast as it goes; the truth is the rig pose times the
// colour camera's extrinsics.
class SimTracking final : public TrackingSequence {
 public:
  static constexpr int kDefaultFrames = 150;  // 5 s at 30 fps, as long as tum_fr1_rpy

  SimTracking(const std::string& options, int max_frames)
      : max_frames_(max_frames > 0 ? max_frames : kDefaultFrames) {
    std::string spec = "realtime=0,trajectory=orbit";
    if (!options.empty()) spec += "," + options;
    spec += fmt::format(",frames={}", max_frames_);
    const sim::SimOptions o = sim::parse_sim_options(spec);
    if (!o.ground_truth) throw std::invalid_argument("sim: eval tracking needs truth=1");
    rig_ = sim::make_sim_rig(o);
    name_ = options.empty() ? "sim" : "sim:" + options;
    camera_ = rig_.calibration.rgb.intrinsics();
    description_ = "sim: " + describe(camera_, rig_.calibration.rgb.distortion());
    undistort_ = std::make_unique<Undistorter>(camera_, rig_.calibration.rgb.distortion());
  }
  const std::string& name() const override { return name_; }
  const PinholeIntrinsics& camera() const override { return camera_; }
  const std::string& camera_description() const override { return description_; }
  std::optional<TrackingFrame> next() override {
    if (max_frames_ > 0 && delivered_ >= max_frames_) return std::nullopt;
    RgbdFrame f;
    const ReadResult r = rig_.rgbd->read(f, std::chrono::seconds(10));
    if (r == ReadResult::EndOfStream) return std::nullopt;
    if (r != ReadResult::Frame)
      throw std::runtime_error("sim: RGB-D read failed: " + rig_.rgbd->last_error());
    if (!f.truth || !f.truth->rig_pose) throw std::runtime_error("sim: a frame without truth");
    TrackingFrame out{f.timestamp_ns, std::move(f.colour), std::move(f.depth),
                      *f.truth->rig_pose * rig_.calibration.T_rig_rgb};
    undistort_->apply(out);
    ++delivered_;
    return out;
  }

 private:
  Rig rig_;
  int max_frames_;
  std::string name_, description_;
  PinholeIntrinsics camera_;
  std::unique_ptr<Undistorter> undistort_;
  int delivered_ = 0;
};

}  // namespace

std::optional<TumPublishedCamera> tum_camera_for_folder(const std::string& folder_name) {
  static const std::regex sensor_re("(^|[^a-z0-9])(fr|freiburg)([123])([^0-9]|$)",
                                    std::regex::icase);
  std::smatch m;
  if (!std::regex_search(folder_name, m, sensor_re)) return std::nullopt;
  const int sensor = m[3].str()[0] - '0';
  switch (sensor) {
    case 1:
      return TumPublishedCamera{
          1, {640, 480, 517.3, 516.5, 318.6, 255.3}, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}};
    case 2:
      return TumPublishedCamera{
          2, {640, 480, 520.9, 521.0, 325.1, 249.7}, {0.2312, -0.7849, -0.0033, -0.0001, 0.9172}};
    default:  // TUM publishes no distortion for fr3
      return TumPublishedCamera{3, {640, 480, 535.4, 539.2, 320.1, 247.6}, {}};
  }
}

std::unique_ptr<TrackingSequence> open_tracking_sequence(const std::string& spec, int max_frames) {
  if (spec == "sim" || spec.starts_with("sim:"))
    return std::make_unique<SimTracking>(spec.size() > 4 ? spec.substr(4) : "", max_frames);
  if (!spec.starts_with("tum:"))
    throw std::invalid_argument("dataset '" + spec +
                                "': expected tum:DIR[?calibration=FILE] or sim[:OPTIONS]");
  std::string dir = spec.substr(4), calibration;
  if (const auto q = dir.find('?'); q != std::string::npos) {
    const std::string query = dir.substr(q + 1);
    dir.resize(q);
    if (!query.starts_with("calibration=") || query.size() == 12)
      throw std::invalid_argument("dataset '" + spec + "': the only option is ?calibration=FILE");
    calibration = query.substr(12);
    if (!fs::is_regular_file(calibration))
      throw std::invalid_argument("calibration file " + calibration + " does not exist");
  }
  if (dir.empty()) throw std::invalid_argument("dataset '" + spec + "': no directory");
  if (!fs::is_directory(dir))
    throw std::invalid_argument("TUM sequence " + dir + " is not a directory");
  return std::make_unique<TumTracking>(dir, calibration, max_frames);
}

}  // namespace probeless::eval
