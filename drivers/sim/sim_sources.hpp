#pragma once
// The synthetic rig's two sources. Internal to drivers/sim: others open them through
// make_sim_rig().
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>
#include <vector>

#include "drivers/sim/sim_moving_scene.hpp"
#include "drivers/sim/sim_renderer.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "drivers/sim/sim_world.hpp"
#include "drivers/sim/worker_pool.hpp"

namespace probeless::sim {

// The arm, or none: it stays out of the calibration views, which are of the board alone.
inline const Occluder* arm_in_view(const SimOptions& options, const Occluder& arm) {
  return options.trajectory == TrajectoryKind::Calibration ? nullptr : &arm;
}

// Everything that moves in front of the room at time t: the arm (or, in a moving-object scene,
// that scene's objects instead), and the near hand when SimOptions::near_occluder (placed
// from the colour camera's pose, so both sources agree).
inline Occluder scene_occluders(const SimWorld& world, const SimOptions& options, double t,
                                const Pose& T_world_rgb) {
  Occluder o = options.scene == MovingScene::None ? world.occluder(t, T_world_rgb.translation)
                                                  : moving_scene_objects(options.scene, t);
  if (options.near_occluder)
    for (const Capsule& c : SimWorld::near_hand(t, T_world_rgb)) o.capsules.push_back(c);
  return o;
}

// Frame index -> time and wall-clock pacing, shared by both sources' logic.
class FramePacer {
 public:
  // start_s: the scripted world time of frame 0 (SimOptions::start_s); timestamps still
  // start at start_ns.
  FramePacer(TimestampNs start_ns, double fps, bool realtime, double start_s = 0)
      : start_ns_(start_ns), fps_(fps), realtime_(realtime), start_s_(start_s) {}
  bool realtime() const { return realtime_; }
  void restart(TimestampNs start_ns) { start_ns_ = start_ns; }
  // World time of a frame: what the trajectory, the lamps and the arm are evaluated at.
  double seconds(std::int64_t index) const { return start_s_ + index / fps_; }
  TimestampNs timestamp(std::int64_t index) const {
    return start_ns_ + static_cast<TimestampNs>(std::llround(index * 1e9 / fps_));
  }
  // The newest frame index whose time has come (realtime).
  std::int64_t latest_due(TimestampNs now) const;
  // Sleeps until `deadline` if that is within `timeout` of now; false when it is not.
  static bool wait_until(TimestampNs deadline, std::chrono::milliseconds timeout);

 private:
  TimestampNs start_ns_;
  double fps_;
  bool realtime_;
  double start_s_;
};

struct RigGeometry {
  Pose T_rig_rgb, T_rig_fisheye;
  double fx, fy, cx, cy;
  int width, height;
};

class SimRgbdSource final : public RgbdSource {
 public:
  SimRgbdSource(std::shared_ptr<const SimWorld> world, const SimOptions& options,
                const RigGeometry& geometry, TimestampNs start_ns);
  ReadResult read(RgbdFrame& frame, std::chrono::milliseconds timeout) override;
  SourceState state() const override { return state_.load(); }
  std::string name() const override { return "sim"; }

  // Renders frame `index` (no pacing): the same index always gives the same frame.
  void render_frame(std::int64_t index, RgbdFrame& frame);
  // SimOptions::prerender: frames 0..count-1 rendered now, read from memory later.
  void prerender(std::int64_t count);
  void restart_clock(TimestampNs start_ns) { pacer_.restart(start_ns); }

 private:
  struct Metering {
    Eigen::Vector3d log_mean;  // per channel, of linear radiance
  };
  const Metering& meter(std::int64_t index);
  void auto_exposure(std::int64_t index, double& gain, Eigen::Vector3d& white_balance);

  std::shared_ptr<const SimWorld> world_;
  SimOptions options_;
  RigGeometry geometry_;
  FramePacer pacer_;
  WorkerPool pool_;
  SimRenderer renderer_;
  SimRenderer meter_renderer_;
  std::map<std::int64_t, Metering> metering_;
  std::vector<RgbdFrame> prerendered_;
  TimestampNs last_stamp_ns_ = 0;  // stamp_on_read: strictly increasing
  std::int64_t next_ = 0;
  TimestampNs stall_wall_end_ = 0;
  std::atomic<SourceState> state_{SourceState::Streaming};
};

class SimFisheyeSource final : public FisheyeSource {
 public:
  SimFisheyeSource(std::shared_ptr<const SimWorld> world, const SimOptions& options,
                   const RigGeometry& geometry, std::shared_ptr<const CameraModel> camera,
                   TimestampNs start_ns);
  ReadResult read(FisheyeFrame& frame, std::chrono::milliseconds timeout) override;
  SourceState state() const override { return state_.load(); }
  std::string name() const override { return "sim"; }
  void set_next_exposure(const ExposureStamp& exposure) override;

  void render_frame(std::int64_t index, const ExposureStamp& exposure, FisheyeFrame& frame);
  void prerender(std::int64_t count);
  void restart_clock(TimestampNs start_ns) { pacer_.restart(start_ns); }

 private:
  // The scene's radiance at frame `index` and its truth: what does not depend on the exposure.
  // The live path leaves the radiance in the renderer (no 3 MB copy per frame).
  struct Scene {
    ImageRGBF radiance;
    std::shared_ptr<const FrameTruth> truth;
  };
  void render_scene(std::int64_t index, Scene& scene, bool keep_radiance);
  void expose(std::int64_t index, const ImageRGBF& radiance,
              const std::shared_ptr<const FrameTruth>& truth, const ExposureStamp& exposure,
              FisheyeFrame& frame);
  // Everything of `frame` but its pixels: index, time, format, exposure, truth.
  void stamp(std::int64_t index, const std::shared_ptr<const FrameTruth>& truth,
             const ExposureStamp& exposure, FisheyeFrame& frame) const;

  std::shared_ptr<const SimWorld> world_;
  SimOptions options_;
  RigGeometry geometry_;
  FramePacer pacer_;
  WorkerPool pool_;
  SimRenderer renderer_;
  std::int64_t end_index_;
  std::vector<Scene> prerendered_;
  // Exposed prerendered scenes by (scene, time, gain), with SimOptions::fisheye_scenes; at
  // most kMaxKept frames (6 MB each at 1024 px), emptied when full (the bracket moved on).
  static constexpr std::size_t kMaxKept = 64;
  std::map<std::tuple<std::int64_t, double, double>, ImageRGB16> kept_;
  std::int64_t next_ = 0;
  std::mutex exposure_mutex_;
  ExposureStamp exposure_;
  std::atomic<SourceState> state_{SourceState::Streaming};
};

}  // namespace probeless::sim
