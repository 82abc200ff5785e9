#include "drivers/sim/sim_rig.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/ocam.hpp"
#include "core/depth_noise.hpp"
#include "drivers/sim/sim_calibration_views.hpp"
#include "drivers/sim/sim_moving_scene.hpp"
#include "drivers/sim/sim_sources.hpp"

namespace probeless::sim {

namespace {

[[noreturn]] void bad(std::string_view key, std::string_view value, std::string_view expected) {
  throw std::invalid_argument("sim option '" + std::string(key) + "': expected " +
                              std::string(expected) + ", got '" + std::string(value) + "'");
}

template <typename T>
T parse_number(std::string_view key, std::string_view value, std::string_view expected) {
  T out{};
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), out);
  if (ec != std::errc() || end != value.data() + value.size()) bad(key, value, expected);
  return out;
}

bool parse_bool(std::string_view key, std::string_view value) {
  if (value == "1" || value == "true" || value == "on" || value == "yes") return true;
  if (value == "0" || value == "false" || value == "off" || value == "no") return false;
  bad(key, value, "0 or 1");
}

double parse_positive(std::string_view key, std::string_view value, double max) {
  const auto v = parse_number<double>(key, value, "a positive number");
  if (!(v > 0 && v <= max)) bad(key, value, "a number in (0, " + std::to_string(max) + "]");
  return v;
}

// Rigs opened with the same seed share one world (building one bakes its lighting, a few
// hundred milliseconds); it lives as long as a source uses it.
std::shared_ptr<const SimWorld> shared_world(std::uint64_t seed, bool board) {
  static std::mutex mutex;
  static std::map<std::pair<std::uint64_t, bool>, std::weak_ptr<const SimWorld>> worlds;
  std::lock_guard lock(mutex);
  if (auto world = worlds[{seed, board}].lock()) return world;
  auto world = std::make_shared<const SimWorld>(seed, board);
  worlds[{seed, board}] = world;
  return world;
}

}  // namespace

// The rig: colour (and registered depth) camera at the rig origin looking forward (rig +y),
// the fisheye 8 cm above it looking up (rig +z) with the rig's forward at the top of its image.
Pose rgb_in_rig() {
  Eigen::Matrix3d r;
  r << Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY();
  Pose p;
  p.rotation = Eigen::Quaterniond(r);
  return p;
}

Pose fisheye_in_rig() {
  Eigen::Matrix3d r;
  r << -Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ();
  Pose p;
  p.rotation = Eigen::Quaterniond(r);
  p.translation = Eigen::Vector3d(0.0, -0.02, 0.08);
  return p;
}

SimOptions parse_sim_options(std::string_view spec) {
  SimOptions o;
  std::size_t pos = 0;
  while (pos <= spec.size()) {
    const std::size_t end = std::min(spec.find_first_of(",&", pos), spec.size());
    const std::string_view item = spec.substr(pos, end - pos);
    pos = end + 1;
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    const std::string_view key = item.substr(0, eq);
    if (eq == std::string_view::npos) bad(key, "", "key=value");
    const std::string_view value = item.substr(eq + 1);
    if (key == "seed") {
      o.seed = parse_number<std::uint64_t>(key, value, "an unsigned integer");
    } else if (key == "trajectory") {
      if (value == "static")
        o.trajectory = TrajectoryKind::Static;
      else if (value == "orbit")
        o.trajectory = TrajectoryKind::Orbit;
      else if (value == "handheld")
        o.trajectory = TrajectoryKind::Handheld;
      else if (value == "tabletop")
        o.trajectory = TrajectoryKind::Tabletop;
      else if (value == "calibration")
        o.trajectory = TrajectoryKind::Calibration;
      else
        bad(key, value, "static, orbit, handheld, tabletop or calibration");
    } else if (key == "board") {
      o.board = parse_bool(key, value);
    } else if (key == "near_occluder") {
      o.near_occluder = parse_bool(key, value);
    } else if (key == "scene") {
      const auto scene = find_moving_scene(value);
      if (!scene) bad(key, value, "one of " + moving_scene_names(", "));
      o.scene = *scene;
    } else if (key == "stamp") {
      o.stamp = parse_bool(key, value);
    } else if (key == "edge_samples") {
      o.edge_samples = parse_number<int>(key, value, "an integer");
      if (o.edge_samples < 1 || o.edge_samples > 8) bad(key, value, "1..8");
    } else if (key == "fps" || key == "rgbd_fps") {
      o.rgbd_fps = parse_positive(key, value, 1000);
    } else if (key == "fisheye_fps") {
      o.fisheye_fps = parse_positive(key, value, 1000);
    } else if (key == "realtime") {
      o.realtime = parse_bool(key, value);
    } else if (key == "fisheye_realtime") {
      o.fisheye_realtime = parse_bool(key, value);
    } else if (key == "fisheye_size") {
      o.fisheye_size = parse_number<int>(key, value, "an integer");
      if (o.fisheye_size < 64 || o.fisheye_size > 1024) bad(key, value, "64..1024");
    } else if (key == "fisheye_bits") {
      o.fisheye_bit_depth = parse_number<int>(key, value, "8 or 12");
      if (o.fisheye_bit_depth != 8 && o.fisheye_bit_depth != 12) bad(key, value, "8 or 12");
    } else if (key == "fisheye_fov") {
      o.fisheye_fov_deg = parse_positive(key, value, 240);
    } else if (key == "fisheye_ocam") {
      if (value.empty()) bad(key, value, "the path of an OCamCalib calib_results.txt");
      o.fisheye_ocam = std::string(value);
    } else if (key == "fisheye_ocam_model") {
      if (value != "ocam" && value != "kannala_brandt") bad(key, value, "ocam or kannala_brandt");
      o.fisheye_ocam_as_kannala_brandt = value == "kannala_brandt";
    } else if (key == "prerender") {
      o.prerender = parse_number<std::int64_t>(key, value, "a frame count");
      if (o.prerender < 0 || o.prerender > 100000) bad(key, value, "0..100000 frames");
    } else if (key == "fisheye_repeat") {
      o.fisheye_repeat = parse_bool(key, value);
    } else if (key == "stamp_on_read") {
      o.stamp_on_read = parse_bool(key, value);
    } else if (key == "fisheye_scenes") {
      o.fisheye_scenes = parse_number<int>(key, value, "a scene count");
      if (o.fisheye_scenes < 0 || o.fisheye_scenes > 100000) bad(key, value, "0..100000 scenes");
    } else if (key == "frames" || key == "max_frames") {
      o.max_frames = parse_number<std::int64_t>(key, value, "an integer");
    } else if (key == "stall") {
      const std::size_t colon = value.find(':');
      if (colon == std::string_view::npos) bad(key, value, "BEGIN:END frame indices");
      o.stall_begin = parse_number<std::int64_t>(key, value.substr(0, colon), "BEGIN:END");
      o.stall_end = parse_number<std::int64_t>(key, value.substr(colon + 1), "BEGIN:END");
      if (o.stall_begin < 0 || o.stall_end < o.stall_begin) bad(key, value, "0 <= BEGIN <= END");
    } else if (key == "stall_every") {
      o.stall_every = parse_number<std::int64_t>(key, value, "a frame count");
      if (o.stall_every < 0) bad(key, value, ">= 0 frames");
    } else if (key == "truth" || key == "ground_truth") {
      o.ground_truth = parse_bool(key, value);
    } else if (key == "threads") {
      o.render_threads = parse_number<int>(key, value, "an integer");
      if (o.render_threads < 1 || o.render_threads > 64) bad(key, value, "1..64");
    } else if (key == "start") {
      o.start_s = parse_number<double>(key, value, "seconds");
      if (!(o.start_s >= 0 && o.start_s <= 86400)) bad(key, value, "0..86400 seconds");
    } else {
      throw std::invalid_argument(
          "sim option '" + std::string(key) +
          "': unknown (known: seed, trajectory, fps, rgbd_fps, fisheye_fps, realtime, "
          "fisheye_realtime, fisheye_size, fisheye_bits, fisheye_fov, fisheye_ocam, "
          "fisheye_ocam_model, "
          "frames, "
          "prerender, fisheye_repeat, fisheye_scenes, stamp_on_read, stall, stall_every, "
          "truth, "
          "threads, start, board, near_occluder, edge_samples, stamp, scene)");
    }
  }
  return o;
}

namespace {

// An OCamCalib calib_results.txt (a few hundred bytes; anything past 64 KiB is not one).
std::shared_ptr<const OCamCamera> read_ocam_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("sim: fisheye_ocam: cannot open " + path);
  std::string text(64 * 1024 + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > 64 * 1024)
    throw std::invalid_argument("sim: fisheye_ocam: " + path +
                                " is larger than 64 KiB, not an OCamCalib calib_results.txt");
  return std::make_shared<const OCamCamera>(OCamCamera::parse(text, path));
}

// A Kannala-Brandt model of the lens `ocam` describes: the same centre and image, and the
// radius of each angle from the axis least-squares fitted by f theta (1 + k1 theta^2 + ... +
// k4 theta^8) over the angles the model covers (the shared sample file: 0.066 px RMS, 0.13 px
// at most inside the frame; tests/unit/sim/sim_ocam_test.cpp).
std::shared_ptr<const CameraModel> kannala_brandt_fit(const OCamCamera& ocam) {
  const auto centre = ocam.project(Eigen::Vector3d(0, 0, 1));
  if (!centre) throw std::invalid_argument("sim: fisheye_ocam: the model misses its axis");
  constexpr int kSamples = 400, kAzimuths = 8;
  const double max_theta = ocam.max_angle();
  Eigen::MatrixXd a(kSamples * kAzimuths, 5);
  Eigen::VectorXd b(kSamples * kAzimuths);
  int rows = 0;
  for (int i = 1; i <= kSamples; ++i) {
    const double theta = max_theta * i / kSamples;
    for (int j = 0; j < kAzimuths; ++j) {
      const double phi = 2 * std::numbers::pi * j / kAzimuths;
      const auto px = ocam.project(Eigen::Vector3d(
          std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
      if (!px) continue;
      for (int k = 0; k < 5; ++k) a(rows, k) = std::pow(theta, 2 * k + 1);
      b(rows++) = (*px - *centre).norm();
    }
  }
  const Eigen::VectorXd c = a.topRows(rows).colPivHouseholderQr().solve(b.head(rows));
  KannalaBrandtParams p;
  p.width = ocam.width();
  p.height = ocam.height();
  p.fx = p.fy = c(0);
  p.cx = centre->x();
  p.cy = centre->y();
  for (int k = 0; k < 4; ++k) p.k[static_cast<std::size_t>(k)] = c(k + 1) / c(0);
  p.max_theta = max_theta;
  return std::make_shared<const KannalaBrandtCamera>(p);
}

std::shared_ptr<const CameraModel> fisheye_of(const SimOptions& options) {
  if (options.fisheye_ocam.empty())
    return std::make_shared<const KannalaBrandtCamera>(
        KannalaBrandtCamera::equidistant(options.fisheye_size, options.fisheye_fov_deg));
  const auto ocam = read_ocam_file(options.fisheye_ocam);
  if (options.fisheye_ocam_as_kannala_brandt) return kannala_brandt_fit(*ocam);
  return ocam;
}

}  // namespace

Rig make_sim_rig(const SimOptions& options) {
  if (!(options.rgbd_fps > 0) || !(options.fisheye_fps > 0))
    throw std::invalid_argument("sim: frame rates must be positive");
  if (options.fisheye_bit_depth != 8 && options.fisheye_bit_depth != 12)
    throw std::invalid_argument("sim: fisheye_bit_depth must be 8 or 12");
  if (options.render_threads < 1) throw std::invalid_argument("sim: render_threads must be >= 1");
  if (options.edge_samples < 1 || options.edge_samples > 8)
    throw std::invalid_argument("sim: edge_samples must be 1..8");

  Rig rig;
  PinholeIntrinsics k;  // 640 x 480, f 525, centre (319.5, 239.5)
  rig.calibration.rgb = PinholeCamera(k);
  const std::shared_ptr<const CameraModel> fisheye = fisheye_of(options);
  rig.calibration.fisheye = fisheye;
  rig.calibration.T_rig_rgb = rgb_in_rig();
  rig.calibration.T_rig_fisheye = fisheye_in_rig();
  rig.calibration.depth_baseline_m = KinectNoiseParams{}.baseline_m;
  const auto [room_lo, room_hi] = room_bounds();
  rig.scene = {object_anchor(), RoomBox{room_lo, room_hi}};

  const RigGeometry geometry{rig.calibration.T_rig_rgb,
                             rig.calibration.T_rig_fisheye,
                             k.fx,
                             k.fy,
                             k.cx,
                             k.cy,
                             k.width,
                             k.height};
  // The calibration views are views of the board.
  auto world = shared_world(options.seed,
                            options.board || options.trajectory == TrajectoryKind::Calibration);
  const TimestampNs start = monotonic_now_ns();
  auto rgbd = std::make_unique<SimRgbdSource>(world, options, geometry, start);
  auto fish = std::make_unique<SimFisheyeSource>(world, options, geometry, fisheye, start);
  if (options.prerender > 0) {
    rgbd->prerender(options.prerender);
    fish->prerender(options.fisheye_repeat && options.fisheye_scenes > 0
                        ? std::min<std::int64_t>(options.prerender, options.fisheye_scenes)
                        : options.prerender);
    // Frame times count from when the frames can flow, not from before the rendering.
    const TimestampNs now = monotonic_now_ns();
    rgbd->restart_clock(now);
    fish->restart_clock(now);
  }
  rig.rgbd = std::move(rgbd);
  rig.fisheye = std::move(fish);
  return rig;
}

}  // namespace probeless::sim
