#include "app/pipeline/light_capture.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "app/pipeline/scene_objects.hpp"
#include "app/pipeline/thread_name.hpp"
#include "app/render/environment_map.hpp"
#include "kernels/envmap/keyframe_reprojection.hpp"
#include "kernels/hdr/colour_exposure.hpp"
#include "kernels/light/colour_fill.hpp"
#include "kernels/light/light_estimator.hpp"
#include "kernels/light/sh_projector.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless {
namespace {

// A bracket cycle is 4 frames; two cycles ride out one slow update without losing a level.
constexpr std::size_t kQueue = 8;
// RGB-D poses kept for interpolation: 2 s at 30 Hz covers any fisheye latency.
constexpr std::size_t kPoses = 64;
// Snapshots for the renderer at 4 Hz: each one costs the renderer a prefilter (~11 ms of CPU
// at 128 px faces) and measured at 10 Hz the render stage's p50 went from 15 to 36 ms under
// load (`bench pipeline`, docs/performance.md); 250 ms still leaves half of the 0.5 s issue
// #6 allows the objects to follow a lamp switch.
constexpr TimestampNs kPublishIntervalNs = 250'000'000;
// The colour camera's auto exposure moves in steps over a few frames; 4 estimates a second
// follow it without copying every colour frame.
constexpr TimestampNs kColourExposureIntervalNs = 250'000'000;
// The SH of a snapshot come from the keyframe box-averaged to this face size (as
// LightEstimatorConfig::sh_face_size: 5 bands need far fewer texels than 128 px faces).
constexpr int kShFaceSize = 32;
// The other keyframes only fill what the nearest did not observe: bilinear there, at 0.4x
// Catmull-Rom's cost, measured the same (`eval render` seeds 1-3, 2026-11-26).
constexpr envmap::Resampling kOtherKeyframesResampling = envmap::Resampling::Bilinear;

envmap::ImageRGBAF box_average(const envmap::ImageRGBAF& texels, int m) {
  const int n = envmap::face_size_of(texels);
  const int k = n / m;
  envmap::ImageRGBAF out = envmap::make_texels(m);
  for (int row = 0; row < 6 * m; ++row)
    for (int x = 0; x < m; ++x)
      for (int c = 0; c < 4; ++c) {
        double sum = 0;
        for (int j = 0; j < k; ++j)
          for (int i = 0; i < k; ++i) sum += texels.at(x * k + i, row * k + j, c);
        out.at(x, row, c) = static_cast<float>(sum / (k * k));
      }
  return out;
}

// [light] room (docs/configuration.md): the room box parallax takes, if any.
std::optional<envmap::RoomBox> room_of(const ServiceConfig& c, const RigScene& scene) {
  if (c.light_room == "box") return envmap::RoomBox{c.light_room_min, c.light_room_max};
  const std::optional<RoomBox>& rig_room = scene.room;
  // The default: the rig's room when it knows one, as the sim does (so `probeless run` lights
  // the objects from the keyframe reprojected to them); a real room's is not known without a
  // config.
  if (c.light_room == "auto") return rig_room;
  if (c.light_room == "sim") {
    if (!rig_room)
      throw std::invalid_argument(
          "light capture: [light] room = \"sim\" needs the sim source, not " + c.source +
          " (use room = \"box\" with the room's extent)");
    return rig_room;
  }
  return std::nullopt;
}

}  // namespace

struct LightCapture::Estimator {
  std::unique_ptr<ComputeContext> ctx;
  std::unique_ptr<light::LightEstimator> light;
  std::unique_ptr<ColourExposureEstimator> colour;
  std::unique_ptr<light::ShProjector> sh;
  light::ColourFill colour_fill;  // its buffers live between snapshots
};

LightCapture::LightCapture(const ServiceConfig& config, const RigCalibration& calibration,
                           const RigScene& scene, std::shared_ptr<const PoseHistory> poses)
    : config_(config),
      calibration_(calibration),
      estimator_(std::make_unique<Estimator>()),
      service_poses_(std::move(poses)),
      pacing_(config.light_update_hz) {
  if (!calibration_.fisheye)
    throw std::invalid_argument("light capture: the rig calibration has no fisheye model");
  room_ = room_of(config_, scene);
  // The objects are lit from the keyframe nearest to them (thesis ch. 6): their mean position,
  // each placed as scene_objects.cpp places it.
  for (const ObjectConfig& o : config_.objects) anchor_ += object_position(o, scene);
  if (!config_.objects.empty()) anchor_ /= static_cast<double>(config_.objects.size());
  // With a room box the light is seen from 10 cm above that (the sim's light_probe_position()
  // for objects on its table anchor): the centre of a small object, not its foot.
  light_point_ = anchor_ + Eigen::Vector3d(0, 0, 0.1);
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

void LightCapture::offer_rgbd(const RgbdFrame& frame) {
  {
    std::lock_guard lock(mutex_);
    if (!want_rgbd_) return;
    want_rgbd_ = false;
  }
  auto copy = std::make_shared<const RgbdFrame>(frame);
  std::lock_guard lock(mutex_);
  rgbd_ = std::move(copy);
}

std::optional<Pose> LightCapture::rig_pose_at(
    TimestampNs t, const std::shared_ptr<const FrameTruth>& truth) const {
  // The service's poses are in the anchored world, which the source's truth need not be.
  // The wait: the processing thread runs a frame or two behind the fisheye.
  if (service_poses_) return service_poses_->wait_at(t, std::chrono::milliseconds(100));
  if (truth && truth->rig_pose) return truth->rig_pose;
  std::lock_guard lock(mutex_);
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

bool LightCapture::initialise() {
  try {
    ComputeOptions options;
    if (!config_.cl_platform.empty()) options.selector.platform_substring = config_.cl_platform;
    if (!config_.cl_device.empty()) options.selector.device_substring = config_.cl_device;
    estimator_->ctx = std::make_unique<ComputeContext>(options);
    light::LightEstimatorConfig lc;
    lc.keyframes.face_size = config_.light_face_size;
    lc.keyframes.new_keyframe_distance_m = config_.light_keyframe_distance_m;
    lc.keyframes.max_keyframes = config_.light_max_keyframes;
    lc.time_stages = false;  // one wait per frame; the service reports the whole update
    // Push-pull and the SH only for the snapshots (publish(): 4 Hz), not per fisheye frame.
    lc.fill_every_frame = false;
    lc.room = room_;
    if (lc.room && !config_.objects.empty()) lc.sh_position = light_point_;
    estimator_->light = std::make_unique<light::LightEstimator>(
        *estimator_->ctx, *calibration_.fisheye, calibration_.T_rig_fisheye, lc);
    estimator_->sh = std::make_unique<light::ShProjector>(kShFaceSize);
    if (config_.light_face_size % kShFaceSize != 0)
      throw std::invalid_argument(fmt::format("light capture: face size {} is not a multiple of {}",
                                              config_.light_face_size, kShFaceSize));
    ColourExposureParams cp;
    cp.fisheye = lc.hdr;
    estimator_->colour = std::make_unique<ColourExposureEstimator>(
        calibration_.rgb, calibration_.fisheye, calibration_.T_rig_rgb, calibration_.T_rig_fisheye,
        cp);
  } catch (const std::exception& e) {
    fail(e.what());
    return false;
  }
  std::lock_guard lock(mutex_);
  state_ = "running";
  return true;
}

void LightCapture::run(std::stop_token stop, StageStats& stats, HeartbeatRegistry& heartbeats) {
  if (!initialise()) return;
  name_this_thread("pl-light");  // after the OpenCL context: see Pipeline::process
  // Watched from its first light frame on: that one builds the OpenCL programs (seconds on
  // PoCL), and frames before it only wait for the tracker's first pose.
  Heartbeat heartbeat;
  while (!stop.stop_requested()) {
    if (!heartbeat) {
      std::lock_guard lock(mutex_);
      if (processed_ > 0) heartbeat = heartbeats.add("light");
    }
    heartbeat.beat();
    FisheyeFrame frame;
    {
      std::unique_lock lock(mutex_);
      if (!arrived_.wait_for(lock, stop, std::chrono::milliseconds(100),
                             [&] { return !queue_.empty(); }))
        continue;
      frame = std::move(queue_.front());
      queue_.pop_front();
    }
    if (admit(frame) && !process(frame, &stats)) return;
  }
}

bool LightCapture::admit(const FisheyeFrame& frame) {
  if (pacing_.admit(frame.exposure, frame.timestamp_ns)) return true;
  std::lock_guard lock(mutex_);
  skipped_ = pacing_.skipped();
  return false;
}

bool LightCapture::process(const FisheyeFrame& frame, StageStats* stats) {
  {
    std::lock_guard lock(mutex_);
    if (state_ != "running") return false;
  }
  const std::optional<Pose> pose = rig_pose_at(frame.timestamp_ns, frame.truth);
  if (!pose && service_poses_) {
    // Tracking lost or not started: a keyframe built at a guessed pose would smear.
    std::lock_guard lock(mutex_);
    ++paused_;
    return true;
  }
  const auto t0 = std::chrono::steady_clock::now();
  try {
    const auto& keyframe = estimator_->light->process(frame, pose.value_or(Pose::identity()));
    if (stats) stats->record("light", ms_since(t0));
    std::lock_guard lock(mutex_);
    ++processed_;
    if (!pose) ++without_pose_;
    keyframes_ = static_cast<int>(estimator_->light->keyframes().keyframes().size());
    keyframes_dropped_ = estimator_->light->keyframes().dropped();
    kept_.clear();
    for (const auto& k : estimator_->light->keyframes().keyframes())
      kept_.emplace_back(k->id, k->position);
    active_keyframe_ = keyframe.id;
  } catch (const std::exception& e) {
    fail(e.what());
    return false;
  }
  try {
    update_colour_exposure(frame);
  } catch (const std::exception& e) {
    // A colour frame the estimator cannot use (sizes not the calibration's) must not stop
    // the light: say it once and go on with the previous estimate.
    spdlog::warn("light capture: colour exposure: {}", e.what());
    estimator_->colour.reset();
    std::lock_guard lock(mutex_);
    colour_error_ = e.what();
  }
  try {
    const auto p0 = std::chrono::steady_clock::now();
    if (publish(frame) && stats) stats->record("light_publish", ms_since(p0));
  } catch (const std::exception& e) {
    fail(e.what());
    return false;
  }
  return true;
}

// Keyframes and the light point do not move: a keyframe's map is built the first time it is
// reprojected (15 ms at 192 px faces) and kept.
LightCapture::Reprojected& LightCapture::reprojected(const envmap::Keyframe& keyframe) {
  Reprojected& r = reprojected_[keyframe.id];
  if (!r.map) {
    const int n = config_.light_face_size;
    r.map.emplace(n, keyframe.position, room_, light_point_, n, 1);
  }
  return r;
}

// What the nearest keyframe never observed from the light point, from the keyframes that did
// (envmap::fill_unobserved): measured with `eval render` on the sim (2 s orbit), the band of
// window just above the object's horizon was 80 % of the chrome sphere's error. The others
// hold the light of when the rig was last near them, so they fill only unobserved texels.
// A dropped keyframe's map and texels go with it (~8 MB at 192 px faces); ids are never reused,
// so an entry left behind could only leak, never be read for another keyframe.
void LightCapture::forget_dropped_keyframes() {
  const envmap::KeyframeSet& set = estimator_->light->keyframes();
  std::erase_if(reprojected_, [&](const auto& entry) { return !set.find(entry.first); });
}

int LightCapture::fill_from_other_keyframes(envmap::ImageRGBAF& texels,
                                            const envmap::Keyframe& nearest) {
  std::vector<const envmap::ImageRGBAF*> others;
  for (const auto& k : estimator_->light->keyframes().keyframes()) {
    if (k->id == nearest.id || k->updates == 0) continue;
    Reprojected& r = reprojected(*k);
    if (r.texels.pixel_count() == 0 || r.updates != k->updates) {
      r.texels = r.map->apply(estimator_->light->download(*k), kOtherKeyframesResampling);
      r.updates = k->updates;
    }
    others.push_back(&r.texels);
  }
  return envmap::fill_unobserved(texels, others);
}

// The colour camera's exposure against a medium-level frame (the level with the most usable
// samples, docs/light-capture.md). The estimator keeps its previous value on too few matches.
void LightCapture::update_colour_exposure(const FisheyeFrame& frame) {
  if (!estimator_->colour || frame.exposure.level != BracketLevel::Medium) return;
  std::shared_ptr<const RgbdFrame> rgbd;
  {
    std::lock_guard lock(mutex_);
    rgbd = std::move(rgbd_);
    rgbd_.reset();
    if (frame.timestamp_ns - last_colour_exposure_ns_ >= kColourExposureIntervalNs)
      want_rgbd_ = true;  // the next colour frame is copied for the next medium frame
  }
  if (!rgbd) return;
  last_colour_exposure_ns_ = frame.timestamp_ns;
  estimator_->colour->update(*rgbd, frame);
  fill_rgbd_ = std::move(rgbd);
}

bool LightCapture::publish(const FisheyeFrame& frame) {
  if (last_publish_ns_ != 0 && frame.timestamp_ns - last_publish_ns_ < kPublishIntervalNs)
    return false;
  last_publish_ns_ = frame.timestamp_ns;
  forget_dropped_keyframes();
  const envmap::Keyframe* keyframe = estimator_->light->keyframes().nearest(anchor_);
  if (!keyframe) return false;
  const ShRgb active_sh = estimator_->light->sh_of_active();
  int keyframe_filled_texels = 0;
  auto snap = std::make_shared<LightSnapshot>();
  snap->timestamp_ns = frame.timestamp_ns;
  snap->keyframe_id = keyframe->id;
  snap->position = keyframe->position;
  snap->texels = estimator_->light->download(*keyframe);
  if (room_) {
    // The environment as the objects see it (docs/light-capture.md "Parallax"): one
    // Catmull-Rom sample per texel at the keyframe's resolution, on the CPU at the publishing
    // rate.
    snap->texels = reprojected(*keyframe).map->apply(snap->texels, envmap::Resampling::CatmullRom);
    snap->position = light_point_;
    keyframe_filled_texels = fill_from_other_keyframes(snap->texels, *keyframe);
  }
  int filled_texels = 0;
  if (config_.light_colour_fill && fill_rgbd_ && estimator_->colour &&
      estimator_->colour->estimate().valid) {
    // Below the fisheye's horizon, the colour camera's view (kernels/light/colour_fill.hpp).
    if (const auto T_world_rig = rig_pose_at(fill_rgbd_->timestamp_ns, fill_rgbd_->truth)) {
      const auto filled = estimator_->colour_fill.fill(
          snap->texels, snap->position, *fill_rgbd_, calibration_.rgb.intrinsics(),
          *T_world_rig * calibration_.T_rig_rgb, estimator_->colour->estimate().e);
      filled_texels = filled.filled_texels;
    }
  }
  snap->sh = estimator_->sh->project(box_average(snap->texels, kShFaceSize));
  {
    auto environment =
        std::make_shared<render::Environment>(render::make_environment(snap->texels, snap->sh));
    environment->levels = std::make_shared<const render::EnvironmentLevels>(
        render::prepare_levels(*environment, environment_scratch_));
    snap->environment = std::move(environment);
  }
  if (estimator_->colour) {
    snap->colour_exposure = estimator_->colour->estimate().e;
    snap->colour_exposure_valid = estimator_->colour->estimate().valid;
  }
  std::lock_guard lock(mutex_);
  sh_ = active_sh;
  colour_filled_texels_ = filled_texels;
  reprojected_count_ = reprojected_.size();
  keyframe_filled_texels_ = keyframe_filled_texels;
  snap->version = ++snapshot_version_;
  snapshot_ = std::move(snap);
  return true;
}

std::shared_ptr<const LightSnapshot> LightCapture::latest_light() const {
  std::lock_guard lock(mutex_);
  return snapshot_;
}

nlohmann::json LightCapture::status() const {
  std::lock_guard lock(mutex_);
  nlohmann::json j = {{"state", state_},
                      {"frames", processed_},
                      {"dropped", dropped_},
                      {"skipped", skipped_},
                      {"update_hz", config_.light_update_hz},
                      {"frames_without_pose", without_pose_},
                      {"frames_paused_without_pose", paused_},
                      {"keyframes", keyframes_},
                      {"keyframes_dropped", keyframes_dropped_},
                      {"max_keyframes", config_.light_max_keyframes},
                      {"reprojected_keyframes", reprojected_count_},
                      {"active_keyframe", active_keyframe_},
                      {"room", room_ ? (config_.light_room == "box" ? "box" : "sim") : "off"}};
  nlohmann::json kept = nlohmann::json::array();
  for (const auto& [id, p] : kept_)
    kept.push_back({{"id", id}, {"position", {p.x(), p.y(), p.z()}}});
  j["kept"] = std::move(kept);
  if (sh_) {
    // L00 times Y00 = the mean radiance over the sphere, per channel (up to the constant the
    // HDR conversion leaves).
    const Eigen::Vector3d mean = sh_->c[0] * 0.28209479177387814;
    j["mean_radiance"] = {mean.x(), mean.y(), mean.z()};
  }
  if (snapshot_) {
    j["snapshot"] = {{"version", snapshot_->version},
                     {"keyframe", snapshot_->keyframe_id},
                     {"colour_filled_texels", colour_filled_texels_},
                     {"keyframe_filled_texels", keyframe_filled_texels_}};
    j["colour_exposure"] = {{"valid", snapshot_->colour_exposure_valid},
                            {"error", colour_error_},
                            {"e",
                             {snapshot_->colour_exposure.x(), snapshot_->colour_exposure.y(),
                              snapshot_->colour_exposure.z()}}};
  }
  if (!error_.empty()) j["error"] = error_;
  return j;
}

std::optional<ShRgb> LightCapture::latest_sh() const {
  std::lock_guard lock(mutex_);
  return sh_;
}

}  // namespace probeless
