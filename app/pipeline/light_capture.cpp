#include "app/pipeline/light_capture.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

#include "app/light/light_estimator.hpp"
#include "app/light/room_proxy.hpp"
#include "core/camera/kannala_brandt.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless {
namespace {

// A bracket cycle is 4 frames; two cycles ride out one slow update without losing a level.
constexpr std::size_t kQueue = 8;
// RGB-D poses kept for interpolation: 2 s at 30 Hz covers any fisheye latency.
constexpr std::size_t kPoses = 64;

const KannalaBrandtCamera& kannala_brandt(const RigCalibration& calibration) {
  const auto* kb = dynamic_cast<const KannalaBrandtCamera*>(calibration.fisheye.get());
  if (!kb)
    throw std::invalid_argument(
        "light capture: the fisheye model must be Kannala-Brandt (the update kernel's model)");
  return *kb;
}

bool is_sim(const std::string& source) {
  return source == "sim" || source.starts_with("sim:");
}

// [light] room (docs/configuration.md): the room box parallax takes, if any.
std::optional<envmap::RoomBox> room_of(const ServiceConfig& c) {
  if (c.light_room == "box") return envmap::RoomBox{c.light_room_min, c.light_room_max};
  if (c.light_room == "sim") {
    if (!is_sim(c.source))
      throw std::invalid_argument(
          "light capture: [light] room = \"sim\" needs the sim source, not " + c.source +
          " (use room = \"box\" with the room's extent)");
    return light::sim_room_box();
  }
  return std::nullopt;
}

// Where an object takes its light from: 10 cm above where it stands (the sim's
// light_probe_position() for the default object on the table anchor).
Eigen::Vector3d object_light_point(const ObjectConfig& o) {
  return o.position.value_or(sim::object_anchor()) + Eigen::Vector3d(0, 0, 0.1);
}

}  // namespace

struct LightCapture::Estimator {
  std::unique_ptr<ComputeContext> ctx;
  std::unique_ptr<light::LightEstimator> light;
};

LightCapture::LightCapture(const ServiceConfig& config, const RigCalibration& calibration)
    : config_(config), calibration_(calibration), estimator_(std::make_unique<Estimator>()) {
  (void)kannala_brandt(calibration_);  // fail at start, not on the first frame
  (void)room_of(config_);
}

LightCapture::~LightCapture() = default;

void LightCapture::push(FisheyeFrame frame) {
  {
    std::lock_guard lock(mutex_);
    queue_.push_back(std::move(frame));
    if (queue_.size() > kQueue) {
      queue_.pop_front();
      ++dropped_;
    }
  }
  arrived_.notify_one();
}

void LightCapture::add_rig_pose(TimestampNs t, const Pose& T_world_rig) {
  std::lock_guard lock(mutex_);
  if (!poses_.empty() && t <= poses_.back().first) return;
  poses_.emplace_back(t, T_world_rig);
  if (poses_.size() > kPoses) poses_.pop_front();
}

std::optional<Pose> LightCapture::rig_pose_at(const FisheyeFrame& frame) const {
  if (frame.truth && frame.truth->rig_pose) return frame.truth->rig_pose;
  std::lock_guard lock(mutex_);
  const TimestampNs t = frame.timestamp_ns;
  for (std::size_t i = 1; i < poses_.size(); ++i) {
    const auto& [t0, p0] = poses_[i - 1];
    const auto& [t1, p1] = poses_[i];
    if (t0 <= t && t <= t1)
      return interpolate(p0, p1, static_cast<double>(t - t0) / static_cast<double>(t1 - t0));
  }
  return std::nullopt;
}

// The light stage stops; the picture goes on without it and /status says why.
void LightCapture::fail(const std::string& what) {
  spdlog::error("light capture: {}", what);
  std::lock_guard lock(mutex_);
  state_ = "failed";
  error_ = what;
}

void LightCapture::run(std::stop_token stop, StageStats& stats) {
  try {
    ComputeOptions options;
    if (!config_.cl_platform.empty()) options.selector.platform_substring = config_.cl_platform;
    if (!config_.cl_device.empty()) options.selector.device_substring = config_.cl_device;
    estimator_->ctx = std::make_unique<ComputeContext>(options);
    light::LightEstimatorConfig lc;
    lc.keyframes.face_size = config_.light_face_size;
    lc.keyframes.new_keyframe_distance_m = config_.light_keyframe_distance_m;
    lc.time_stages = false;  // one wait per frame; the service reports the whole update
    lc.room = room_of(config_);
    if (lc.room && !config_.objects.empty())
      lc.sh_position = object_light_point(config_.objects.front());
    estimator_->light = std::make_unique<light::LightEstimator>(
        *estimator_->ctx, kannala_brandt(calibration_).params(), calibration_.T_rig_fisheye, lc);
  } catch (const std::exception& e) {
    return fail(e.what());
  }
  {
    std::lock_guard lock(mutex_);
    state_ = "running";
  }
  while (!stop.stop_requested()) {
    FisheyeFrame frame;
    {
      std::unique_lock lock(mutex_);
      if (!arrived_.wait_for(lock, stop, std::chrono::milliseconds(100),
                             [&] { return !queue_.empty(); }))
        continue;
      frame = std::move(queue_.front());
      queue_.pop_front();
    }
    const std::optional<Pose> pose = rig_pose_at(frame);
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const auto& keyframe = estimator_->light->process(frame, pose.value_or(Pose::identity()));
      stats.record(
          "light",
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      std::lock_guard lock(mutex_);
      ++processed_;
      if (!pose) ++without_pose_;
      keyframes_ = static_cast<int>(estimator_->light->keyframes().keyframes().size());
      active_keyframe_ = keyframe.id;
      sh_ = estimator_->light->sh();
    } catch (const std::exception& e) {
      return fail(e.what());
    }
  }
}

nlohmann::json LightCapture::status() const {
  std::lock_guard lock(mutex_);
  nlohmann::json j = {{"state", state_},           {"frames", processed_},
                      {"dropped", dropped_},       {"frames_without_pose", without_pose_},
                      {"keyframes", keyframes_},   {"active_keyframe", active_keyframe_},
                      {"room", config_.light_room}};
  if (sh_) {
    // L00 times Y00 = the mean radiance over the sphere, per channel (up to the constant the
    // HDR conversion leaves).
    const Eigen::Vector3d mean = sh_->c[0] * 0.28209479177387814;
    j["mean_radiance"] = {mean.x(), mean.y(), mean.z()};
  }
  if (!error_.empty()) j["error"] = error_;
  return j;
}

std::optional<ShRgb> LightCapture::latest_sh() const {
  std::lock_guard lock(mutex_);
  return sh_;
}

}  // namespace probeless
