#include "lab/eval/render_eval.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "app/pipeline/light_capture.hpp"
#include "app/pipeline/scene_objects.hpp"
#include "app/render/renderer.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "drivers/sim/sim_world.hpp"
#include "kernels/envmap/envmap_types.hpp"
#include "lab/eval/light_eval.hpp"
#include "lab/eval/render_eval_common.hpp"

namespace probeless::eval {
namespace {

using render::ImageRGBAF;

// The sim's scripted lamp switch the run is placed around (SimWorld::lamp_state: lamp B is on
// for the first half of every 12 s period).
constexpr double kSwitchWorldS = 6.0;
// The tolerance for "matching ground truth" after a lamp switch.
constexpr double kLampTolerance = 0.10;
// A ground pixel is in the shadow region when the truth's change there is at least this share
// of its largest: the contact shadow, not the faint far tail of the transfer difference.
constexpr double kShadowShare = 0.10;

double mean_luminance(const ImageRGBAF& img) {
  double sum = 0;
  int n = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x)
      if (img.at(x, y, 3) > 0.5f) {
        sum += luminance(img, x, y);
        ++n;
      }
  return n > 0 ? sum / n : 0.0;
}

}  // namespace

double relative_rgb_error(const ImageRGBAF& a, const ImageRGBAF& b, const std::vector<bool>& mask) {
  if (a.width() != b.width() || a.height() != b.height() || mask.size() != b.pixel_count())
    throw std::invalid_argument("relative_rgb_error: sizes differ");
  double num = 0, den = 0;
  for (int y = 0; y < b.height(); ++y)
    for (int x = 0; x < b.width(); ++x) {
      if (!mask[static_cast<std::size_t>(y * b.width() + x)]) continue;
      for (int c = 0; c < 3; ++c) {
        const double e = a.at(x, y, c) - b.at(x, y, c);
        num += e * e;
        den += static_cast<double>(b.at(x, y, c)) * b.at(x, y, c);
      }
    }
  return den > 0 ? std::sqrt(num / den) : 0.0;
}

RenderEvalReport evaluate_render_sim(const RenderEvalOptions& o) {
  ServiceConfig config = o.config;
  if (config.source != "sim" && !config.source.starts_with("sim:"))
    throw std::invalid_argument("eval render: only the sim has ground-truth light");
  if (config.objects.empty()) throw std::invalid_argument("eval render: no objects configured");
  if (!(o.orbit_s > 0) || !(o.after_switch_s > 0))
    throw std::invalid_argument("eval render: the orbit and after-switch times must be > 0");
  if (o.truth_supersample < 1 || o.sphere_image_size < 16)
    throw std::invalid_argument("eval render: bad truth supersampling or sphere image size");

  const double start = kSwitchWorldS - o.orbit_s;
  if (start < 0) throw std::invalid_argument("eval render: orbit longer than 6 s");
  const std::string spec = fmt::format("realtime=0,trajectory=orbit,start={}{}", start,
                                       o.sim_spec.empty() ? "" : "," + o.sim_spec);
  const sim::SimOptions sim_options = sim::parse_sim_options(spec);
  Rig rig = sim::make_sim_rig(sim_options);
  place_objects(config.objects, rig.scene);
  LightCapture capture(config, rig.calibration, rig.scene);
  initialise_or_throw(capture);

  // The objects as the service makes them (PRT baked or read from the cache).
  const std::vector<render::VirtualObject> objects =
      make_scene_objects(config.objects, config.ground, default_prt_cache_dir());
  std::vector<render::VirtualObject> diffuse;  // what the lamp response watches
  for (const auto& obj : objects)
    if (obj.material.shading == render::Material::Shading::PrtDiffuse ||
        obj.material.shading == render::Material::Shading::ShDiffuse)
      diffuse.push_back(obj);
  if (diffuse.empty())
    for (const auto& obj : objects)
      if (obj.material.shading != render::Material::Shading::GroundShadow) diffuse.push_back(obj);
  render::Renderer renderer(renderer_config_for(objects));

  const auto world = std::make_shared<const sim::SimWorld>(sim_options.seed);
  const Eigen::Vector3d light_point = sim::light_probe_position();
  const int n = config.light_face_size;
  const std::array<std::shared_ptr<const render::Environment>, 2> truth{
      truth_environment(world, light_point, 0, n, o.truth_supersample),
      truth_environment(world, light_point, 1, n, o.truth_supersample)};
  const double scale = sim::fisheye_radiance_per_converted();

  SimLightFeed feed(rig, capture);
  Pose T_world_rig = Pose::identity();
  const int frames =
      static_cast<int>(std::lround((o.orbit_s + o.after_switch_s) * sim_options.fisheye_fps));
  RenderEvalReport report;
  report.switch_t_s = kSwitchWorldS;
  std::shared_ptr<const LightSnapshot> compared;
  render::Camera compare_camera;
  std::uint64_t seen_version = 0;
  for (int i = 0; i < frames; ++i) {
    // The colour frames up to this fisheye frame give the light stage its poses and its
    // exposure estimate, and the camera the objects are seen from.
    feed.step([&](const RgbdFrame& rgbd) { T_world_rig = *rgbd.truth->rig_pose; });
    ++report.fisheye_frames;

    const auto snap = capture.latest_light();
    if (!snap || snap->version == seen_version) continue;
    seen_version = snap->version;
    ++report.snapshots;
    const double t = start + static_cast<double>(i) / sim_options.fisheye_fps;
    if (t < kSwitchWorldS) {
      compared = snap;
      compare_camera = {rig.calibration.rgb.intrinsics(), T_world_rig * rig.calibration.T_rig_rgb};
      report.compare_t_s = t;
    }
    if (!compared) continue;
    // The lamp response: the diffuse objects' mean radiance from the captured light against
    // the truth of the lamp state at the snapshot's time, seen from the compared camera.
    const int lamps = sim::SimWorld::lamp_state(t);
    LampSample s;
    s.t_s = t;
    s.truth = mean_luminance(render_float(renderer, compare_camera, lit_by(diffuse, truth[lamps])));
    s.captured = mean_luminance(
        render_float(renderer, compare_camera, lit_by(diffuse, scaled_environment(*snap, scale))));
    s.rel_error = s.truth > 0 ? std::abs(s.captured - s.truth) / s.truth : 0.0;
    report.lamp.push_back(s);
  }
  if (!compared) throw std::runtime_error("eval render: no light snapshot before the switch");

  // The lamp response.
  std::optional<std::size_t> settled;
  for (std::size_t k = 0; k < report.lamp.size(); ++k) {
    const LampSample& s = report.lamp[k];
    if (s.t_s < kSwitchWorldS) {
      report.lamp_rel_error_before = s.rel_error;
      settled.reset();
      continue;
    }
    if (s.rel_error > kLampTolerance)
      settled.reset();
    else if (!settled)
      settled = k;
  }
  if (settled) report.lamp_response_s = report.lamp[*settled].t_s - kSwitchWorldS;
  if (!report.lamp.empty()) {
    report.lamp_rel_error_final = report.lamp.back().rel_error;
    const auto before = std::find_if(report.lamp.rbegin(), report.lamp.rend(),
                                     [](const LampSample& s) { return s.t_s < kSwitchWorldS; });
    if (before != report.lamp.rend() && before->truth > 0)
      report.truth_drop = report.lamp.back().truth / before->truth;
  }

  // Objects and their ground shadow, from the snapshot before the switch and from the truth.
  const int lamps_before = sim::SimWorld::lamp_state(report.compare_t_s);
  const auto captured_env = scaled_environment(*compared, scale);
  const ImageRGBAF cap = render_float(renderer, compare_camera, lit_by(objects, captured_env));
  const ImageRGBAF tru =
      render_float(renderer, compare_camera, lit_by(objects, truth[lamps_before]));
  std::vector<bool> object_mask(tru.pixel_count()), shadow_mask(tru.pixel_count());
  double largest_change = 0;
  for (int y = 0; y < tru.height(); ++y)
    for (int x = 0; x < tru.width(); ++x)
      if (!(tru.at(x, y, 3) > 0.5f))
        largest_change = std::max(largest_change, std::abs(luminance(tru, x, y)));
  for (int y = 0; y < tru.height(); ++y)
    for (int x = 0; x < tru.width(); ++x) {
      const auto i = static_cast<std::size_t>(y * tru.width() + x);
      object_mask[i] = tru.at(x, y, 3) > 0.5f && cap.at(x, y, 3) > 0.5f;
      shadow_mask[i] = !(tru.at(x, y, 3) > 0.5f) && largest_change > 0 &&
                       std::abs(luminance(tru, x, y)) >= kShadowShare * largest_change;
      if (object_mask[i]) ++report.object_pixels;
      if (shadow_mask[i]) {
        ++report.shadow_pixels;
        report.shadow_mean_captured += luminance(cap, x, y);
        report.shadow_mean_truth += luminance(tru, x, y);
      }
    }
  if (report.shadow_pixels > 0) {
    report.shadow_mean_captured /= report.shadow_pixels;
    report.shadow_mean_truth /= report.shadow_pixels;
  }
  report.object_rel_error = relative_rgb_error(cap, tru, object_mask);
  report.shadow_rel_error = relative_rgb_error(cap, tru, shadow_mask);

  // The chrome sphere (thesis Fig. 4.13 / 6.9): a mirror ball at the light point.
  const render::VirtualObject ball = chrome_sphere(light_point);
  const render::Camera ball_camera =
      sphere_camera(light_point, compare_camera.T_world_camera.translation, o.sphere_image_size);
  const ImageRGBAF ball_cap = render_float(renderer, ball_camera, lit_by({ball}, captured_env));
  const ImageRGBAF ball_tru =
      render_float(renderer, ball_camera, lit_by({ball}, truth[lamps_before]));
  std::vector<bool> ball_mask(ball_tru.pixel_count());
  for (int y = 0; y < ball_tru.height(); ++y)
    for (int x = 0; x < ball_tru.width(); ++x) {
      const bool in = ball_tru.at(x, y, 3) > 0.5f;
      ball_mask[static_cast<std::size_t>(y * ball_tru.width() + x)] = in;
      report.sphere_pixels += in ? 1 : 0;
    }
  report.sphere_rel_rmse = relative_rgb_error(ball_cap, ball_tru, ball_mask);
  std::vector<bool> upper = ball_mask, lower = ball_mask;
  for (std::size_t i = 0; i < ball_mask.size(); ++i)
    (i < ball_mask.size() / 2 ? lower : upper)[i] = false;
  report.sphere_rel_rmse_upper = relative_rgb_error(ball_cap, ball_tru, upper);
  report.sphere_rel_rmse_lower = relative_rgb_error(ball_cap, ball_tru, lower);

  if (!o.dump_dir.empty()) {
    write_panels(o.dump_dir + "/chrome_sphere.png", ball_cap, ball_tru, ball_mask, true);
    write_panels(o.dump_dir + "/objects.png", cap, tru, object_mask, false);
    // The two environments as the renderer took them: faces +x, -x, +y, -y, +z, -z top down.
    const ImageRGBAF& env_cap = captured_env->faces;
    write_panels(o.dump_dir + "/environments.png", env_cap, truth[lamps_before]->faces,
                 std::vector<bool>(env_cap.pixel_count(), true), true);
  }
  return report;
}

}  // namespace probeless::eval
