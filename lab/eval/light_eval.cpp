#include "lab/eval/light_eval.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/exposure_count.hpp"
#include "drivers/bracket/bracket_sequencer.hpp"
#include "drivers/io/png.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "drivers/sim/sim_renderer.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "drivers/sim/sim_world.hpp"
#include "kernels/envmap/keyframe_reprojection.hpp"

namespace probeless::light {

namespace {

// Noise of the sim's 12-bit fisheye for the sequencer's predictions (docs/sim.md): read
// 3 e- x 0.3839 DN/e- and 0.5 DN ADC; shot noise at full scale sqrt(3839 DN x 0.3839 DN/e-).
constexpr double kReadNoiseDn = 1.26, kFullScaleNoiseDn = 38.4;

envmap::ImageRGBAF from_cubemap(const Cubemap& cube) {
  const int n = cube.face_size;
  envmap::ImageRGBAF t = envmap::make_texels(n);
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        for (int c = 0; c < 3; ++c) t.at(x, f * n + y, c) = cube.faces[f].at(x, y, c);
        t.at(x, f * n + y, 3) = 1.0F;
      }
  return t;
}

// Strips of m x 6m side by side, 4x enlarged, log10 radiance from -1 to 4.5 over 0..255;
// texels whose alpha is 0 darkened.
void write_comparison(const std::string& path,
                      const std::vector<const envmap::ImageRGBAF*>& strips) {
  const int m = envmap::face_size_of(*strips[0]), z = 4, gap = 4;
  const int w = static_cast<int>(strips.size()) * (m * z + gap);
  ImageRGB8 out(w, 6 * m * z);
  for (std::size_t s = 0; s < strips.size(); ++s)
    for (int y = 0; y < 6 * m * z; ++y)
      for (int x = 0; x < m * z; ++x) {
        const int tx = x / z, ty = y / z;
        const bool seen = strips[s]->at(tx, ty, 3) > 0;
        for (int c = 0; c < 3; ++c) {
          const double v = std::log10(std::max(1e-3F, strips[s]->at(tx, ty, c)));
          double g = std::clamp((v + 1.0) / 5.5, 0.0, 1.0) * 255.0;
          if (!seen) g *= 0.4;
          out.at(static_cast<int>(s) * (m * z + gap) + x, y, c) = static_cast<std::uint8_t>(g);
        }
      }
  write_png(path, out);
}

// Where the RMSE comes from: per texel |est - truth|^2 (RGB) as a share of the comparison's
// sum of |truth|^2, on a log scale from 1e-5 (black) to 1e-1 (white) of it, one strip per
// comparison; unobserved texels blue.
void write_error(
    const std::string& path,
    const std::vector<std::pair<const envmap::ImageRGBAF*, const envmap::ImageRGBAF*>>& pairs) {
  const int m = envmap::face_size_of(*pairs[0].first), z = 4, gap = 4;
  ImageRGB8 out(static_cast<int>(pairs.size()) * (m * z + gap), 6 * m * z);
  for (std::size_t s = 0; s < pairs.size(); ++s) {
    const envmap::ImageRGBAF &est = *pairs[s].first, &truth = *pairs[s].second;
    double den = 0;
    for (int y = 0; y < 6 * m; ++y)
      for (int x = 0; x < m; ++x)
        if (est.at(x, y, 3) > 0)
          for (int c = 0; c < 3; ++c)
            den += static_cast<double>(truth.at(x, y, c)) * truth.at(x, y, c);
    for (int y = 0; y < 6 * m * z; ++y)
      for (int x = 0; x < m * z; ++x) {
        const int tx = x / z, ty = y / z;
        std::uint8_t* px = &out.at(static_cast<int>(s) * (m * z + gap) + x, y, 0);
        if (!(est.at(tx, ty, 3) > 0)) {
          px[2] = 96;
          continue;
        }
        double e2 = 0;
        for (int c = 0; c < 3; ++c) {
          const double e = est.at(tx, ty, c) - truth.at(tx, ty, c);
          e2 += e * e;
        }
        const double share = den > 0 ? e2 / den : 0;
        const double g = std::clamp((std::log10(std::max(share, 1e-12)) + 5.0) / 4.0, 0.0, 1.0);
        px[0] = px[1] = px[2] = static_cast<std::uint8_t>(g * 255.0);
      }
  }
  write_png(path, out);
}

std::vector<bool> observed_of(const envmap::ImageRGBAF& texels) {
  std::vector<bool> observed(texels.pixel_count());
  for (int y = 0; y < texels.height(); ++y)
    for (int x = 0; x < texels.width(); ++x)
      observed[static_cast<std::size_t>(y * texels.width() + x)] = texels.at(x, y, 3) > 0;
  return observed;
}

double relative_error(const ShRgb& est, const ShRgb& truth, int count) {
  double num = 0, den = 0;
  for (int k = 0; k < count; ++k) {
    num += (est.c[k] - truth.c[k]).squaredNorm();
    den += truth.c[k].squaredNorm();
  }
  return den > 0 ? std::sqrt(num / den) : 0.0;
}

}  // namespace

// The room seen from `position` as a cubemap of n-px faces, one ray per texel centre: each
// face is a 90-degree pinhole view. GL faces are mirror images of a right-handed camera
// (s x t = -major), so the camera's x runs along -s and the image is flipped back.
envmap::ImageRGBAF render_truth_cubemap(const std::shared_ptr<const sim::SimWorld>& world,
                                        const Eigen::Vector3d& position, int lamp_state, int n,
                                        const sim::Occluder* objects,
                                        envmap::ImageRGBAF* object_hits) {
  static const std::array<std::array<Eigen::Vector3d, 3>, 6> kAxes{{
      {{{0, 0, -1}, {0, -1, 0}, {1, 0, 0}}},   // +X: s, t, major
      {{{0, 0, 1}, {0, -1, 0}, {-1, 0, 0}}},   // -X
      {{{1, 0, 0}, {0, 0, 1}, {0, 1, 0}}},     // +Y
      {{{1, 0, 0}, {0, 0, -1}, {0, -1, 0}}},   // -Y
      {{{1, 0, 0}, {0, -1, 0}, {0, 0, 1}}},    // +Z
      {{{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}}},  // -Z
  }};
  sim::WorkerPool pool(2);
  const double f = 0.5 * n, c = 0.5 * (n - 1);
  sim::SimRenderer renderer(world, n, n, f, f, c, c, &pool);
  envmap::ImageRGBAF out = envmap::make_texels(n);
  if (object_hits) *object_hits = envmap::make_texels(n);
  for (int face = 0; face < 6; ++face) {
    Eigen::Matrix3d r;
    r << -kAxes[face][0], kAxes[face][1], kAxes[face][2];
    Pose T_world_camera;
    T_world_camera.rotation = Eigen::Quaterniond(r);
    T_world_camera.translation = position;
    // The flags (with depth) say where the objects are the first hit.
    renderer.render(T_world_camera, lamp_state, objects, object_hits != nullptr);
    const ImageRGBF& rad = renderer.radiance();
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        for (int ch = 0; ch < 3; ++ch) out.at(x, face * n + y, ch) = rad.at(n - 1 - x, y, ch);
        out.at(x, face * n + y, 3) = 1.0F;
        if (!object_hits) continue;
        const bool hit = (renderer.flags().at(n - 1 - x, y) & sim::kFlagOccluder) != 0;
        for (int ch = 0; ch < 3; ++ch) object_hits->at(x, face * n + y, ch) = hit ? 1.0F : 0.0F;
        object_hits->at(x, face * n + y, 3) = 1.0F;
      }
  }
  return out;
}

envmap::ImageRGBAF average_observed(const envmap::ImageRGBAF& texels, int m,
                                    std::vector<bool>& observed) {
  const int n = envmap::face_size_of(texels);
  if (m < 1 || n % m != 0) throw std::invalid_argument("average_observed: m must divide n");
  const int k = n / m;
  envmap::ImageRGBAF out = envmap::make_texels(m);
  observed.assign(static_cast<std::size_t>(6 * m * m), false);
  for (int row = 0; row < 6 * m; ++row) {
    const int face = row / m, y = row - face * m;
    for (int x = 0; x < m; ++x) {
      double sum[3] = {0, 0, 0};
      bool all = true;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          const int sx = x * k + i, sy = face * n + y * k + j;
          all = all && texels.at(sx, sy, 3) > 0;
          for (int c = 0; c < 3; ++c) sum[c] += texels.at(sx, sy, c);
        }
      for (int c = 0; c < 3; ++c) out.at(x, row, c) = static_cast<float>(sum[c] / (k * k));
      out.at(x, row, 3) = all ? 1.0F : 0.0F;
      observed[static_cast<std::size_t>(row * m + x)] = all;
    }
  }
  return out;
}

TruthComparison compare_cubemaps(const envmap::ImageRGBAF& est, const envmap::ImageRGBAF& truth,
                                 const std::vector<bool>& observed) {
  const int m = envmap::face_size_of(truth);
  if (est.width() != m || est.height() != 6 * m || observed.size() != est.pixel_count())
    throw std::invalid_argument("compare_cubemaps: sizes differ");
  TruthComparison out;
  double all_num = 0, all_den = 0;
  for (int f = 0; f < 6; ++f) {
    double num = 0, den = 0;
    int count = 0;
    for (int y = 0; y < m; ++y)
      for (int x = 0; x < m; ++x) {
        const int row = f * m + y;
        if (!observed[static_cast<std::size_t>(row * m + x)]) continue;
        ++count;
        for (int c = 0; c < 3; ++c) {
          const double e = est.at(x, row, c) - truth.at(x, row, c);
          num += e * e;
          den += static_cast<double>(truth.at(x, row, c)) * truth.at(x, row, c);
        }
      }
    out.faces[f].observed = count;
    if (count > 0 && den > 0) out.faces[f].relative_rmse = std::sqrt(num / den);
    out.all.observed += count;
    all_num += num;
    all_den += den;
  }
  if (out.all.observed > 0 && all_den > 0) out.all.relative_rmse = std::sqrt(all_num / all_den);
  return out;
}

LightEvalReport evaluate_light_sim(const LightEvalOptions& o) {
  const std::string spec =
      "realtime=0,trajectory=orbit" + (o.sim_spec.empty() ? std::string() : "," + o.sim_spec);
  const sim::SimOptions sim_options = sim::parse_sim_options(spec);
  Rig rig = sim::make_sim_rig(sim_options);
  // The calibration light capture uses, and the pose that takes the sim's rig frame (in which
  // the truth trajectory is) to its rig frame: through the colour camera, which tracking sees.
  RigCalibration calibration = rig.calibration;
  Pose sim_rig_to_calibration_rig;
  if (!o.calibration_file.empty()) {
    calibration = replay::load_rig_calibration(o.calibration_file);
    if (!calibration.fisheye)
      throw std::invalid_argument("eval light: " + o.calibration_file + " has no [fisheye]");
    const CameraModel& truth = *rig.calibration.fisheye;
    if (calibration.fisheye->width() != truth.width() ||
        calibration.fisheye->height() != truth.height())
      throw std::invalid_argument(fmt::format(
          "eval light: {}'s fisheye is {}x{} but the sim's is {}x{} (set --sim fisheye_size)",
          o.calibration_file, calibration.fisheye->width(), calibration.fisheye->height(),
          truth.width(), truth.height()));
    sim_rig_to_calibration_rig = rig.calibration.T_rig_rgb * calibration.T_rig_rgb.inverse();
  }

  ComputeContext ctx;
  LightEstimatorConfig config = o.estimator;
  if (o.room_box) config.room = rig.scene.room;
  LightEstimator estimator(ctx, *calibration.fisheye, calibration.T_rig_fisheye, config);
  BracketSequencer sequencer;
  Trajectory trajectory;  // from the RGB-D stream's truth, as tracking would deliver it
  const auto timeout = std::chrono::milliseconds(5000);
  const int frames = static_cast<int>(std::lround(o.seconds * sim_options.fisheye_fps));
  LightEvalReport report;
  FisheyeFrame frame;
  RgbdFrame rgbd;
  int last_change_cycle = 0;
  std::vector<double> total_ms;  // per frame, LightTimings::total
  for (int i = 0; i < frames; ++i) {
    const ExposureStamp stamp = sequencer.next();
    rig.fisheye->set_next_exposure(stamp);
    if (rig.fisheye->read(frame, timeout) != ReadResult::Frame)
      throw std::runtime_error("eval light: the sim's fisheye stopped");
    while (trajectory.empty() || trajectory.samples().back().timestamp_ns < frame.timestamp_ns) {
      if (rig.rgbd->read(rgbd, timeout) != ReadResult::Frame || !rgbd.truth ||
          !rgbd.truth->rig_pose)
        throw std::runtime_error("eval light: the sim's RGB-D stream stopped or has no truth");
      trajectory.append(rgbd.timestamp_ns, *rgbd.truth->rig_pose * sim_rig_to_calibration_rig);
    }
    if (!estimator.process(frame, trajectory))
      throw std::runtime_error("eval light: no rig pose at a fisheye timestamp");
    total_ms.push_back(estimator.last_timings().total.wall_ms);
    if (sequencer.observe(frame.exposure,
                          count_exposure(frame.raw, frame.bit_depth, frame.black_level,
                                         kReadNoiseDn, kFullScaleNoiseDn)))
      last_change_cycle = static_cast<int>(frame.exposure.cycle) + 1;
    ++report.frames;
  }
  report.settle_cycles = last_change_cycle;
  report.total = summarize(std::move(total_ms));
  report.rule = envmap::to_string(o.estimator.update.rule);
  report.scale = sim::fisheye_radiance_per_converted();

  const Eigen::Vector3d probe = sim::light_probe_position();
  const envmap::Keyframe* keyframe = estimator.keyframes().nearest(probe);
  if (!keyframe) throw std::runtime_error("eval light: no keyframe");
  report.keyframes = static_cast<int>(estimator.keyframes().keyframes().size());
  report.keyframe_id = keyframe->id;
  report.keyframe_distance_m = (keyframe->position - probe).norm();
  envmap::ImageRGBAF texels = estimator.download(*keyframe);
  for (int y = 0; y < texels.height(); ++y)
    for (int x = 0; x < texels.width(); ++x)
      for (int c = 0; c < 3; ++c) texels.at(x, y, c) *= static_cast<float>(report.scale);

  const int m = o.compare_face_size;
  const int n = envmap::face_size_of(texels);
  if (n % m != 0)
    throw std::invalid_argument("eval light: the compare size must divide the face size");
  if (!frame.truth || !frame.truth->light) throw std::runtime_error("eval light: no truth light");
  const Cubemap& probe_truth = *frame.truth->light;
  if (probe_truth.face_size != m)
    throw std::runtime_error("eval light: compare_face_size must be the truth's face size");
  const std::optional<envmap::RoomBox>& room = config.room;
  report.room_box = room.has_value();

  // An m-px estimate as seen from `where` (the keyframe reprojected through the room box; at
  // the keyframe's own position, or without a box, its m-px box filter), compared with the
  // truth there over the texels it observed; SH of both (filled texels included: the SH
  // covers the sphere, as the renderer would use it).
  const auto compare = [&](const envmap::ImageRGBAF& est, const envmap::ImageRGBAF& truth,
                           const std::string& what) {
    TruthComparison c = compare_cubemaps(est, truth, observed_of(est));
    c.truth = what;
    const ShRgb est_sh = project_sh(envmap::to_cubemap(est));
    const ShRgb truth_sh = project_sh(envmap::to_cubemap(truth));
    c.sh25_relative_error = relative_error(est_sh, truth_sh, 25);
    c.sh9_relative_error = relative_error(est_sh, truth_sh, 9);
    return c;
  };
  const auto seen_from = [&](const Eigen::Vector3d& where) {
    return envmap::reproject_keyframe(texels, keyframe->position, room, where, m, n / m,
                                      envmap::Resampling::CatmullRom);
  };
  std::vector<bool> unused;
  const envmap::ImageRGBAF est_keyframe = average_observed(texels, m, unused);
  const envmap::ImageRGBAF est_probe = room ? seen_from(probe) : est_keyframe;
  const envmap::ImageRGBAF probe_strip = from_cubemap(probe_truth);
  report.at_probe =
      compare(est_probe, probe_strip,
              room ? "FrameTruth::light (from light_probe_position()), keyframe reprojected there"
                   : "FrameTruth::light (from light_probe_position())");
  report.at_probe_unreprojected = compare(
      est_keyframe, probe_strip, "FrameTruth::light, the keyframe's directions as they are");

  // The same room from where the keyframe was captured: the capture's own error, without the
  // parallax between the keyframe and the object.
  const auto world = std::make_shared<const sim::SimWorld>(sim_options.seed);
  const double t_last = (frames - 1) / sim_options.fisheye_fps;
  const int lamps = sim::SimWorld::lamp_state(t_last);
  std::vector<bool> all_observed;
  const envmap::ImageRGBAF truth_keyframe =
      average_observed(render_truth_cubemap(world, keyframe->position, lamps, n), m, all_observed);
  report.at_keyframe =
      compare(est_keyframe, truth_keyframe, "the room rendered from the keyframe's position");

  const Eigen::Vector3d last_capture =
      (*trajectory.at(frame.timestamp_ns) * calibration.T_rig_fisheye).translation;
  report.keyframe_to_last_capture_m = (last_capture - keyframe->position).norm();
  const envmap::ImageRGBAF truth_last =
      average_observed(render_truth_cubemap(world, last_capture, lamps, n), m, all_observed);
  const envmap::ImageRGBAF est_last = room ? seen_from(last_capture) : est_keyframe;
  report.at_last_capture = compare(est_last, truth_last,
                                   room ? "the room rendered from the fisheye's last position, "
                                          "keyframe reprojected there"
                                        : "the room rendered from the fisheye's last position");

  if (!o.dump_dir.empty())
    write_comparison(o.dump_dir + "/compare.png", {&est_keyframe, &truth_keyframe, &est_probe,
                                                   &probe_strip, &est_last, &truth_last});
  if (!o.dump_dir.empty())
    write_error(
        o.dump_dir + "/error.png",
        {{&est_keyframe, &truth_keyframe}, {&est_probe, &probe_strip}, {&est_last, &truth_last}});
  return report;
}

}  // namespace probeless::light
