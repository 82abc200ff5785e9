#include "kernels/tracking/dense_tracker.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <optional>
#include <stdexcept>

#include "kernels/tracking/frame_pyramid.hpp"
#include "kernels/tracking/keyframe.hpp"
#include "kernels/tracking/normal_equations.hpp"
#include "kernels/tracking/se3.hpp"
#include "kernels/tracking/tracking_device.hpp"

namespace probeless::tracking {

const char* to_string(TrackingState state) {
  switch (state) {
    case TrackingState::Off:
      return "off";
    case TrackingState::Tracking:
      return "tracking";
    case TrackingState::Lost:
      return "lost";
    case TrackingState::Relocalising:
      return "relocalising";
  }
  return "?";
}

namespace {

// Starting t-scales before a level has residuals of its own: a few grey levels (8-bit sensor
// noise and interpolation) and 1 cm at 1 m (Kinect v1, Khoshelham & Elberink 2012).
constexpr double kInitialSigmaPhoto = 8.0;
constexpr double kInitialSigmaGeo = 0.01;
// Floors that keep the weights finite on a perfect (synthetic) match.
constexpr double kMinSigmaPhoto = 0.5;
constexpr double kMinSigmaGeo = 1e-4;
// A keyframe point warped nearer than this is at the lens, not on a surface the frame sees.
constexpr float kMinWarpedDepthM = 0.1f;
// Gains outside this range are not an exposure change but a failed fit.
constexpr double kMinGain = 0.5, kMaxGain = 2.0;

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double rotation_deg(const Pose& p) {
  return Eigen::AngleAxisd(p.rotation).angle() * 180.0 / M_PI;
}

// A motion predicted over more than this many of the last intervals is a guess, not a model.
constexpr double kMaxMotionScale = 4.0;

// The motion `s` times over: rotation angle and translation scaled (small motions).
Pose scaled_motion(const Pose& motion, double s) {
  const Eigen::AngleAxisd r(motion.rotation);
  Pose out;
  out.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(r.angle() * s, r.axis()));
  out.translation = motion.translation * s;
  return out;
}

struct Alignment {
  Pose T_current_keyframe;
  bool accepted = false;
  double visible_fraction = 0, inlier_fraction = 0, residual_rms = 0;
  double gain = 1, bias = 0;
  int iterations = 0;
};

}  // namespace

struct DenseTracker::Impl {
  ComputeContext* ctx = nullptr;
  PinholeIntrinsics camera;
  DenseTrackerParams params;
  std::vector<float> undistort;  // undistortion_map(); empty without distortion
  std::optional<TrackingDevice> device;
  Pose origin;
  TrackingState state = TrackingState::Off;

  FramePyramid current;            // the CPU path's pyramid (the device path's stays on the device)
  std::deque<Keyframe> keyframes;  // back() is the reference
  TimestampNs current_time = 0;    // of the frame being tracked
  int frame_index = -1;            // of the current frame since reset()
  Pose T_world_last;
  Pose last_motion;                              // T_prev_cur of the last tracked pair
  TimestampNs last_time = 0, last_interval = 0;  // of the last tracked frame and pair
  double gain = 1, bias = 0;
  // The current frame's rotation over its readout (rad, camera axes); zero: global shutter.
  std::array<float, 3> readout_rotation{};

  // The rotation over one readout at the angular velocity of `motion` (T_prev_cur) over
  // `interval`; zero without a rolling shutter or without an interval to divide by.
  std::array<float, 3> rotation_over_readout(const Pose& motion, TimestampNs interval) const {
    if (params.rolling_shutter_readout_s <= 0.0 || interval <= 0) return {};
    const Eigen::AngleAxisd r(motion.rotation);
    const Eigen::Vector3d w =
        r.axis() * r.angle() * (params.rolling_shutter_readout_s / (double(interval) * 1e-9));
    return {float(w.x()), float(w.y()), float(w.z())};
  }

  void build_pyramid(const ImageRGB8& colour, const DepthImage& depth_mm) {
    if (device)
      device->build_pyramid(colour, depth_mm, camera, params);
    else
      build_pyramid_reference(colour, depth_mm, camera, params, undistort, current);
  }

  void make_current_keyframe(const Pose& T_world_camera) {
    keyframes.push_back(device ? device->make_keyframe(T_world_camera, params.max_points_per_level,
                                                       readout_rotation)
                               : make_keyframe(current, T_world_camera, params.max_points_per_level,
                                               readout_rotation));
    keyframes.back().id = frame_index;
    keyframes.back().timestamp_ns = current_time;
    keyframes.back().shear_pending =
        params.rolling_shutter_readout_s > 0.0 && readout_rotation == std::array<float, 3>{};
    while (int(keyframes.size()) > params.max_keyframes) keyframes.pop_front();
    gain = 1;
    bias = 0;
  }

  NormalSums sums(Keyframe& kf, int level, const IterationParams& p) {
    if (device) return device->accumulate(kf, level, p);
    return accumulate_cpu(kf.points[std::size_t(level)], current.levels[std::size_t(level)], p);
  }

  bool beyond_keyframe(const Pose& T_keyframe_camera) const {
    return T_keyframe_camera.translation.norm() > params.keyframe_max_translation_m ||
           rotation_deg(T_keyframe_camera) > params.keyframe_max_rotation_deg;
  }
  Alignment align(Keyframe& kf, const Pose& T_init, double gain0, double bias0);
  std::optional<std::pair<Pose, Alignment>> revisit(const Pose& T_world_camera);
  bool accept(const Alignment& a) const {
    return a.visible_fraction >= params.min_visible_fraction &&
           a.inlier_fraction >= params.min_inlier_fraction;
  }
};

// Coarse to fine inverse-compositional Gauss-Newton: the keyframe's Jacobians are fixed, the
// weights, t-scales and brightness model are re-estimated from each iteration's residuals.
Alignment DenseTracker::Impl::align(Keyframe& kf, const Pose& T_init, double gain0, double bias0) {
  Alignment out;
  out.gain = gain0;
  out.bias = bias0;
  Pose T = T_init;
  for (int level = params.levels - 1; level >= 0; --level) {
    const auto& points = kf.points[std::size_t(level)];
    const LevelCamera& c = kf.cameras[std::size_t(level)];
    double var_photo = kInitialSigmaPhoto * kInitialSigmaPhoto;
    double var_geo = kInitialSigmaGeo * kInitialSigmaGeo;
    NormalSums s{};
    for (int it = 0; it < params.max_iterations; ++it) {
      IterationParams p{};
      const Eigen::Matrix3d R = T.rotation.toRotationMatrix();
      for (int i = 0; i < 9; ++i) p.r[i] = float(R(i / 3, i % 3));
      for (int i = 0; i < 3; ++i) p.t[i] = float(T.translation[i]);
      p.fx = c.fx, p.fy = c.fy, p.cx = c.cx, p.cy = c.cy;
      p.inv_gain = float(1.0 / out.gain);
      p.bias = float(out.bias);
      p.inv_var_photo = float(1.0 / var_photo);
      p.inv_var_geo = float(1.0 / var_geo);
      p.nu = params.student_nu;
      p.photo_inlier = params.photometric_inlier;
      p.geo_inlier = params.geometric_inlier_m;
      p.min_depth = kMinWarpedDepthM;
      for (int i = 0; i < 3; ++i) p.readout_rotation[i] = readout_rotation[std::size_t(i)];
      s = sums(kf, level, p);
      ++out.iterations;
      if (s[kPhotoCount] + s[kGeoCount] < 12) break;  // too few residuals for 6 unknowns

      // Kerl et al. (eq. 10): sigma^2 = 1/n sum r^2 (nu + 1) / (nu + r^2 / sigma^2), one
      // fixed-point step per iteration.
      var_photo = std::max(s[kPhotoWeightedSq] / std::max(1.0, s[kPhotoCount]),
                           kMinSigmaPhoto * kMinSigmaPhoto);
      if (s[kGeoCount] > 0)
        var_geo = std::max(s[kGeoWeightedSq] / s[kGeoCount], kMinSigmaGeo * kMinSigmaGeo);
      // Brightness: match the weighted mean and spread of the keyframe's intensities to the
      // current frame's over the same points (robust to misalignment, unlike a regression).
      const double sw = s[kAffineW];
      if (sw > 0) {
        const double mx = s[kAffineX] / sw, my = s[kAffineY] / sw;
        const double vx = s[kAffineXX] / sw - mx * mx, vy = s[kAffineYY] / sw - my * my;
        if (vx > 1.0 && vy > 0.0) {
          out.gain = std::clamp(std::sqrt(vy / vx), kMinGain, kMaxGain);
          out.bias = my - out.gain * mx;
        }
      }

      Eigen::Matrix<double, 6, 6> H;
      Vector6d g;
      for (int a = 0, k = kH; a < 6; ++a) {
        for (int b = a; b < 6; ++b, ++k) H(a, b) = H(b, a) = s[std::size_t(k)];
        g[a] = s[std::size_t(kG + a)];
      }
      H.diagonal() *= 1.0 + 1e-6;  // keeps a rank-deficient view (a plain wall) solvable
      const Vector6d xi = H.ldlt().solve(g);
      if (!xi.allFinite()) break;
      T = T * se3_exp(-xi);
      T.rotation.normalize();  // products of unit quaternions drift off the unit sphere
      // A step's image motion halves per coarser level: the bound is in finest-level pixels.
      if (xi.norm() < params.min_update * double(1 << level)) break;
    }
    if (level == 0) {
      const double n = double(points.size());
      out.visible_fraction = n > 0 ? s[kVisible] / n : 0.0;
      out.inlier_fraction = s[kVisible] > 0 ? s[kInliers] / s[kVisible] : 0.0;
      out.residual_rms = s[kPhotoCount] > 0 ? std::sqrt(s[kPhotoSq] / s[kPhotoCount]) : 0.0;
    }
  }
  out.T_current_keyframe = T;
  out.accepted = accept(out);
  return out;
}

// Before a new keyframe is made, an older kept one that still sees this view as the current
// one must (the same overlap and distance bounds) becomes the reference again, and the frame's
// pose is measured against it. A hand or a head swings back and forth over the same view: each
// new keyframe composes one more alignment's error into every later pose, while a revisited
// keyframe carries only the error it had when it was made (DVO-SLAM, Kerl et al. IROS 2013,
// closes such loops in its graph; here the reference is simply re-used). Of the candidates,
// the one that sees most of this frame wins. Returns the frame's pose against it; the
// keyframe is moved to the back of the list.
std::optional<std::pair<Pose, Alignment>> DenseTracker::Impl::revisit(const Pose& T_world_camera) {
  std::optional<std::pair<Pose, Alignment>> best;
  std::size_t best_index = 0;
  for (std::size_t i = 0; i + 1 < keyframes.size(); ++i) {
    Keyframe& kf = keyframes[i];
    const Pose T_keyframe_camera = kf.T_world_keyframe.inverse() * T_world_camera;
    if (beyond_keyframe(T_keyframe_camera)) continue;
    const Alignment c = align(kf, T_keyframe_camera.inverse(), gain, bias);
    if (!c.accepted || c.visible_fraction < params.keyframe_min_visible ||
        beyond_keyframe(c.T_current_keyframe.inverse()))
      continue;
    if (best && c.visible_fraction <= best->second.visible_fraction) continue;
    best.emplace(kf.T_world_keyframe * c.T_current_keyframe.inverse(), c);
    best_index = i;
  }
  if (best) {
    const auto it = keyframes.begin() + std::ptrdiff_t(best_index);
    std::rotate(it, it + 1, keyframes.end());
  }
  return best;
}

DenseTracker::DenseTracker(ComputeContext* ctx, const PinholeIntrinsics& camera,
                           DenseTrackerParams params)
    : DenseTracker(ctx, PinholeCamera(camera), params) {}

DenseTracker::DenseTracker(ComputeContext* ctx, const PinholeCamera& pinhole,
                           DenseTrackerParams params)
    : impl_(std::make_unique<Impl>()) {
  const PinholeIntrinsics& camera = pinhole.intrinsics();
  if (params.finest_level < 0 || params.finest_level > 1)
    throw std::invalid_argument("tracking: finest_level must be 0 (full) or 1 (half resolution)");
  if (params.levels < 1 || (camera.width >> (params.finest_level + params.levels - 1)) < 8 ||
      (camera.height >> (params.finest_level + params.levels - 1)) < 8)
    throw std::invalid_argument("tracking: the pyramid's coarsest level must be >= 8x8 pixels");
  if (!(params.min_depth_m > 0.0f && params.max_depth_m > params.min_depth_m) ||
      !(params.student_nu > 0.0f))
    throw std::invalid_argument("tracking: needs 0 < min_depth_m < max_depth_m and student_nu > 0");
  if (params.max_keyframes < 1 || params.max_iterations < 1 || params.max_points_per_level < 16)
    throw std::invalid_argument("tracking: max_keyframes, max_iterations and points must be >0");
  impl_->ctx = ctx;
  impl_->camera = camera;
  impl_->params = params;
  impl_->undistort = undistortion_map(pinhole, params.finest_level);
  if (ctx) {
    impl_->device.emplace(*ctx);
    impl_->device->set_undistortion(impl_->undistort);
  }
}

DenseTracker::~DenseTracker() = default;

TrackResult DenseTracker::track(const ImageRGB8& colour, const DepthImage& depth_mm,
                                TimestampNs timestamp_ns) {
  Impl& m = *impl_;
  const auto& k = m.camera;
  if (colour.width() != k.width || colour.height() != k.height || depth_mm.width() != k.width ||
      depth_mm.height() != k.height)
    throw std::invalid_argument("tracking: frame size differs from the colour camera's");
  TrackResult r;
  ++m.frame_index;
  m.current_time = timestamp_ns;
  // Constant velocity: the last pair's motion, scaled to this frame's interval when both are
  // known (a dropped frame doubles it).
  const TimestampNs interval = timestamp_ns - m.last_time;
  const double scale = m.last_interval > 0 && interval > 0
                           ? std::min(double(interval) / double(m.last_interval), kMaxMotionScale)
                           : 1.0;
  const Pose predicted = m.params.constant_velocity
                             ? m.T_world_last * scaled_motion(m.last_motion, scale)
                             : m.T_world_last;
  // The rolling shutter's rotation while this frame was read out: the motion model's angular
  // velocity (none for a first frame or while lost: no velocity is known then).
  m.readout_rotation = m.state == TrackingState::Tracking && m.last_interval > 0
                           ? m.rotation_over_readout(m.last_motion, m.last_interval)
                           : std::array<float, 3>{};
  auto t0 = std::chrono::steady_clock::now();
  m.build_pyramid(colour, depth_mm);
  r.pyramid_ms = ms_since(t0);

  if (m.state == TrackingState::Off) {
    t0 = std::chrono::steady_clock::now();
    m.make_current_keyframe(m.origin);
    r.keyframe_ms = ms_since(t0);
    m.T_world_last = m.origin;
    m.last_motion = Pose::identity();
    m.last_time = timestamp_ns;
    m.last_interval = 0;
    m.state = TrackingState::Tracking;
    r.state = m.state;
    r.T_world_camera = m.origin;
    r.inlier_fraction = r.visible_fraction = 1.0;
    r.keyframes = int(m.keyframes.size());
    r.keyframe_id = m.keyframes.back().id;
    r.new_keyframe = true;
    return r;
  }

  t0 = std::chrono::steady_clock::now();
  Alignment a;
  Keyframe* reference = nullptr;
  std::size_t relocalised_at = 0;
  if (m.state == TrackingState::Tracking) {
    reference = &m.keyframes.back();
    a = m.align(*reference, predicted.inverse() * reference->T_world_keyframe, m.gain, m.bias);
    if (!a.accepted && m.params.constant_velocity) {
      // The camera may have stopped or turned back: start again from the last pose.
      const int before = a.iterations;
      a = m.align(*reference, m.T_world_last.inverse() * reference->T_world_keyframe, m.gain,
                  m.bias);
      a.iterations += before;
    }
  } else {
    // Lost: try every kept keyframe, starting at its own view, and take the best accepted one
    // (the first accepted may be a wrong minimum that just passes the test).
    int iterations = 0;
    for (std::size_t i = m.keyframes.size(); i-- > 0;) {
      const Alignment candidate = m.align(m.keyframes[i], Pose::identity(), 1.0, 0.0);
      iterations += candidate.iterations;
      if (!reference || (candidate.accepted && candidate.inlier_fraction > a.inlier_fraction)) {
        a = candidate;
        if (candidate.accepted) {
          reference = &m.keyframes[i];
          relocalised_at = i;
        }
      }
    }
    a.iterations = iterations;
    r.relocalised = reference != nullptr;
  }
  r.align_ms = ms_since(t0);
  r.iterations = a.iterations;
  r.residual_rms = a.residual_rms;
  r.inlier_fraction = a.inlier_fraction;
  r.visible_fraction = a.visible_fraction;
  r.exposure_gain = a.gain;
  r.exposure_bias = a.bias;

  if (!a.accepted) {
    m.state =
        m.state == TrackingState::Tracking ? TrackingState::Lost : TrackingState::Relocalising;
    r.state = m.state;
    r.T_world_camera = m.T_world_last;  // the last known pose; not meaningful while lost
    r.keyframes = int(m.keyframes.size());
    return r;
  }

  Pose T_world_camera = reference->T_world_keyframe * a.T_current_keyframe.inverse();
  if (reference->shear_pending && !r.relocalised && interval > 0) {
    // The keyframe was made before any velocity was known: its readout shear is removed now,
    // with the angular velocity between it and this frame, and this frame aligned again.
    const Pose motion = reference->T_world_keyframe.inverse() * T_world_camera;
    const TimestampNs since = timestamp_ns - reference->timestamp_ns;
    const auto shear = m.rotation_over_readout(motion, since);
    undo_rolling_shutter(*reference, shear);
    // This frame had no velocity either (it follows a first frame): it turns at the same rate.
    if (m.readout_rotation == std::array<float, 3>{}) m.readout_rotation = shear;
    reference->shear_pending = false;
    if (m.device) {
      reference->device_points.clear();
      m.device->upload_points(*reference);
    }
    const int before = a.iterations;
    const Alignment again = m.align(*reference, a.T_current_keyframe, a.gain, a.bias);
    if (again.accepted) {
      a = again;
      T_world_camera = reference->T_world_keyframe * a.T_current_keyframe.inverse();
    }
    a.iterations += before;
  }
  bool switch_keyframe = a.visible_fraction < m.params.keyframe_min_visible ||
                         m.beyond_keyframe(a.T_current_keyframe.inverse());
  if (switch_keyframe && !r.relocalised) {
    t0 = std::chrono::steady_clock::now();
    if (const auto back = m.revisit(T_world_camera)) {
      T_world_camera = back->first;
      a.gain = back->second.gain;
      a.bias = back->second.bias;
      switch_keyframe = false;
      r.revisited = true;
    }
    r.align_ms += ms_since(t0);
  }
  m.last_motion = r.relocalised ? Pose::identity() : m.T_world_last.inverse() * T_world_camera;
  m.last_interval = r.relocalised ? 0 : interval;
  m.last_time = timestamp_ns;
  m.T_world_last = T_world_camera;
  m.state = TrackingState::Tracking;
  m.gain = a.gain;
  m.bias = a.bias;
  if (r.relocalised) {
    // The keyframe that relocalised us becomes the reference: move it to the back.
    const auto it = m.keyframes.begin() + std::ptrdiff_t(relocalised_at);
    std::rotate(it, it + 1, m.keyframes.end());
  }

  if (switch_keyframe) {
    // The keyframe's points are corrected with the angular velocity just measured.
    m.readout_rotation = m.rotation_over_readout(m.last_motion, m.last_interval);
    t0 = std::chrono::steady_clock::now();
    m.make_current_keyframe(T_world_camera);
    r.keyframe_ms = ms_since(t0);
    r.new_keyframe = true;
  }
  r.state = m.state;
  r.T_world_camera = T_world_camera;
  r.keyframes = int(m.keyframes.size());
  r.keyframe_id = m.keyframes.back().id;
  return r;
}

void DenseTracker::reset(const Pose& T_world_camera) {
  impl_->origin = T_world_camera;
  impl_->keyframes.clear();
  impl_->frame_index = -1;
  impl_->state = TrackingState::Off;
}

TrackingState DenseTracker::state() const {
  return impl_->state;
}
bool DenseTracker::uses_device() const {
  return impl_->ctx != nullptr;
}

}  // namespace probeless::tracking
