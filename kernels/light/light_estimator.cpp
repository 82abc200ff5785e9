#include "kernels/light/light_estimator.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>

#include "core/camera/kannala_brandt.hpp"
#include "kernels/envmap/keyframe_reprojection.hpp"

namespace probeless::light {

namespace {

using Clock = std::chrono::steady_clock;

// CPU time of the whole process (PoCL's threads included): LightStepTime::cpu_ms.
double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

// The image circle beyond which pixels are vignetted border: for Kannala-Brandt where its
// max_theta lands. Other models say no circle (an OCamCalib fit covers the whole frame to its
// corners); the conversion's black margin still drops the unlit border.
HdrConversionParams with_circle(HdrConversionParams p, const CameraModel& camera) {
  const auto* kb = dynamic_cast<const KannalaBrandtCamera*>(&camera);
  if (p.circle_radius == 0 && kb) {
    const KannalaBrandtParams& cam = kb->params();
    const double theta_d = kannala_brandt_distorted_angle(cam.k, cam.max_theta);
    p.circle_cx = static_cast<float>(cam.cx);
    p.circle_cy = static_cast<float>(cam.cy);
    p.circle_radius = static_cast<float>(theta_d * std::min(cam.fx, cam.fy));
  }
  return p;
}

}  // namespace

LightEstimator::LightEstimator(ComputeContext& ctx, const CameraModel& fisheye,
                               const Pose& T_rig_fisheye, const LightEstimatorConfig& config)
    : ctx_(ctx),
      fisheye_(envmap::build_fisheye_lut(fisheye)),
      T_rig_fisheye_(T_rig_fisheye),
      config_(config),
      keyframes_(ctx, config.keyframes),
      update_(ctx, config.update, with_circle(config.hdr, fisheye)),
      push_pull_(ctx),
      downsample_(ctx),
      projector_(config.sh_face_size) {
  if (config_.room) envmap::validate(*config_.room);
}

const envmap::Keyframe& LightEstimator::process(const FisheyeFrame& frame,
                                                const Pose& T_world_rig) {
  const auto t0 = Clock::now();
  const double cpu0 = process_cpu_ms();
  auto t = t0;
  double cpu = cpu0;
  timings_.steps.clear();
  const auto lap = [&](std::string_view step) {
    if (!config_.time_stages) return;
    ctx_.queue().finish();
    const auto now = Clock::now();
    const double cpu_now = process_cpu_ms();
    timings_.steps.push_back(
        {step, std::chrono::duration<double, std::milli>(now - t).count(), cpu_now - cpu});
    t = now;
    cpu = cpu_now;
  };

  // The update reads ~40 % of the frame's pixels, scattered: wrapping the frame's own memory
  // (no copy on PoCL and on boards whose GPU shares it) saved the 6 MB copy, 0.5-0.7 ms
  // (docs/performance.md "Light capture: bench light").
  raw_ = DeviceImage<std::uint16_t, 3>::wrap_host(ctx_.context(), frame.raw);
  lap("upload");

  // Without a room box the environment is taken as distant, so where the fisheye is inside
  // the keyframe's neighbourhood does not move the texels; with one, texels are points on its
  // walls seen from the keyframe's position (docs/light-capture.md "Parallax").
  const Pose T_world_fisheye = T_world_rig * T_rig_fisheye_;
  if (!config_.fill_every_frame) {
    // A new keyframe is seeded from the nearest's texels, filled ones included: fill that
    // first, as every frame's push-pull would have.
    const envmap::Keyframe* near = keyframes_.nearest(T_world_fisheye.translation);
    if (near && (near->position - T_world_fisheye.translation).norm() >
                    config_.keyframes.new_keyframe_distance_m)
      fill(*near);
  }
  envmap::Keyframe& keyframe = keyframes_.for_capture(T_world_fisheye.translation);
  if (keyframes_.dropped() != dropped_seen_) forget_dropped_keyframes();
  envmap::FisheyeView view;
  view.lut = fisheye_;
  view.R_camera_world = T_world_fisheye.rotation.toRotationMatrix().transpose();
  view.room = config_.room;
  view.position = T_world_fisheye.translation;
  view.keyframe_position = keyframe.position;
  const bool bracketing = frame.exposure.level != BracketLevel::Fixed;
  const bool publish = !bracketing || frame.exposure.cycle_position == 3;
  update_.update_raw(raw_, frame.bit_depth, frame.black_level, frame.exposure.exposure, view,
                     publish, keyframe.texels, keyframe.pending);
  ++keyframe.updates;
  lap("update");

  if (config_.fill_every_frame) {
    fill(keyframe);
    lap("push_pull");
    project_sh(keyframe);  // blocking: waits for the whole queue
    lap("sh");
  } else {
    ctx_.queue().finish();
  }
  timings_.total.wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  timings_.total.cpu_ms = process_cpu_ms() - cpu0;
  // raw_ reads frame.raw in place: the blocking download (or finish) above has drained the
  // queue, so nothing uses it after this returns.
  return keyframe;
}

// What is kept here per keyframe goes with it (its SH table: 0.6 MB at 32 px faces).
void LightEstimator::forget_dropped_keyframes() {
  const auto dropped = [&](const auto& entry) { return !keyframes_.find(entry.first); };
  std::erase_if(filled_at_, dropped);
  std::erase_if(reprojected_, dropped);
  if (!keyframes_.find(sh_keyframe_)) sh_keyframe_ = -1;
  dropped_seen_ = keyframes_.dropped();
}

void LightEstimator::fill(const envmap::Keyframe& keyframe) {
  std::uint64_t& filled = filled_at_[keyframe.id];
  if (filled == keyframe.updates && keyframe.updates != 0) return;
  // keyframes_ owns the keyframe; push-pull writes its texels on the device.
  push_pull_.fill(keyframes_.find(keyframe.id)->texels);
  filled = keyframe.updates;
}

void LightEstimator::project_sh(const envmap::Keyframe& keyframe) {
  downsample_.run(keyframe.texels, config_.sh_face_size, small_);
  small_.download(ctx_.queue(), small_host_);  // blocking: waits for the whole queue
  if (config_.room && config_.sh_position) {
    // Seen from the object: the reprojection folded into the projection table, built the
    // first time a keyframe is used (keyframes never move).
    auto it = reprojected_.find(keyframe.id);
    if (it == reprojected_.end())
      it = reprojected_
               .emplace(keyframe.id,
                        ShProjector(config_.sh_face_size,
                                    envmap::reprojection_constants(config_.room, keyframe.position,
                                                                   *config_.sh_position)))
               .first;
    sh_ = it->second.project(small_host_);
  } else {
    sh_ = projector_.project(small_host_);
  }
  sh_keyframe_ = keyframe.id;
  sh_updates_ = keyframe.updates;
}

const ShRgb& LightEstimator::sh_of_active() {
  const int id = keyframes_.active_id();
  const envmap::Keyframe* active = keyframes_.find(id);
  if (!active) return sh_;
  const envmap::Keyframe& keyframe = *active;
  if (sh_keyframe_ == id && sh_updates_ == keyframe.updates) return sh_;
  fill(keyframe);
  project_sh(keyframe);
  return sh_;
}

bool LightEstimator::process(const FisheyeFrame& frame, const Trajectory& rig) {
  const auto pose = rig.at(frame.timestamp_ns);
  if (!pose) return false;
  process(frame, *pose);
  return true;
}

envmap::ImageRGBAF LightEstimator::download(const envmap::Keyframe& keyframe) {
  fill(keyframe);
  return keyframe.texels.download(ctx_.queue());
}

}  // namespace probeless::light
