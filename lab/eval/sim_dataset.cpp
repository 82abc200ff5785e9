#include "lab/eval/sim_dataset.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "app/pipeline/scene_objects.hpp"
#include "app/pipeline/service_config.hpp"
#include "app/render/renderer.hpp"
#include "core/depth_noise.hpp"

namespace probeless::eval {

namespace {

// Takes the protocol's own `lift=` out of `options` (the rest are the sim's).
double take_lift(std::string& options) {
  double lift = 0.0;
  std::string rest;
  std::size_t start = 0;
  while (start <= options.size()) {
    const std::size_t end = std::min(options.find(',', start), options.size());
    const std::string item = options.substr(start, end - start);
    if (item.rfind("lift=", 0) == 0) {
      std::size_t used = 0;
      try {
        lift = std::stod(item.substr(5), &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != item.size() - 5 || !(lift >= 0.0 && lift <= 2.0))
        throw std::invalid_argument("sim option 'lift': metres in 0..2, got '" + item.substr(5) +
                                    "'");
    } else if (!item.empty()) {
      rest += (rest.empty() ? "" : ",") + item;
    }
    start = end + 1;
  }
  options = rest;
  return lift;
}

}  // namespace

SimProtocolOptions parse_sim_protocol(std::string_view options_in) {
  std::string options(options_in);
  const double lift = take_lift(options);
  // Later keys win in parse_sim_options: the protocol's defaults first, the caller's after.
  // edge_samples=4: silhouettes are mixed pixels as a camera's are (16 rays), so the matte's
  // truth is fractional there and the composite error has a true foreground to score.
  const std::string spec =
      "trajectory=tabletop,start=1.5,near_occluder=1,edge_samples=4," + std::string(options);
  SimProtocolOptions o;
  o.sim = sim::parse_sim_options(spec);
  if (o.sim.max_frames >= 0) {
    if (o.sim.max_frames < 2 || o.sim.max_frames > 3000)
      throw std::invalid_argument("sim option 'frames': the sim protocol takes 2..3000 frames");
    o.frames = static_cast<int>(o.sim.max_frames);
  }
  o.sim.max_frames = o.frames;
  o.sim.realtime = false;  // every frame in order
  o.sim.fisheye_realtime = false;
  o.sim.ground_truth = true;
  o.lift_m = lift;
  if (o.sim.trajectory == sim::TrajectoryKind::Calibration)
    throw std::invalid_argument("sim protocol: trajectory=calibration has no virtual objects");
  return o;
}

ImageGray8 dilate_mask(const ImageGray8& seeds, int radius) {
  const int w = seeds.width(), h = seeds.height();
  ImageGray8 rows(w, h), out(w, h);
  for (int y = 0; y < h; ++y) {
    int last = -1000000;  // the nearest seed at or left of x, then the next one right
    std::vector<int> next(static_cast<std::size_t>(w) + 1, 1000000);
    for (int x = w - 1; x >= 0; --x)
      next[static_cast<std::size_t>(x)] =
          seeds.at(x, y) ? x : next[static_cast<std::size_t>(x) + 1];
    for (int x = 0; x < w; ++x) {
      if (seeds.at(x, y)) last = x;
      rows.at(x, y) =
          (x - last <= radius || next[static_cast<std::size_t>(x)] - x <= radius) ? 1 : 0;
    }
  }
  for (int x = 0; x < w; ++x)
    for (int y = 0; y < h; ++y) {
      std::uint8_t v = 0;
      for (int k = std::max(0, y - radius); k <= std::min(h - 1, y + radius) && !v; ++k)
        v = rows.at(x, k);
      out.at(x, y) = v ? 255 : 0;
    }
  return out;
}

namespace {

std::string case_name(const SimProtocolOptions& o) {
  const char* traj = "orbit";
  switch (o.sim.trajectory) {
    case sim::TrajectoryKind::Static:
      traj = "static";
      break;
    case sim::TrajectoryKind::Handheld:
      traj = "handheld";
      break;
    case sim::TrajectoryKind::Tabletop:
      traj = "tabletop";
      break;
    default:
      break;
  }
  std::string name = std::string("sim/") + traj + (o.sim.near_occluder ? "+near" : "");
  if (o.lift_m > 0) name += fmt::format("+lift{:.2f}", o.lift_m);
  return name + "/seed" + std::to_string(o.sim.seed);
}

}  // namespace

void apply_mixed_pixels(const std::vector<MixedPixel>& mixed, EvalFrame& f) {
  if (mixed.empty()) return;
  f.true_foreground = f.colour;
  const std::size_t count = f.truth.pixel_count();
  for (const MixedPixel& m : mixed) {
    if (m.index >= count || !f.mask.data()[m.index]) continue;
    const float v = f.virtual_depth_mm.data()[m.index];
    // Only a pixel split by the virtual surface is fractional: the near layer hides the
    // object and is the foreground, the far one is what the object replaces. With both
    // layers on one side the centre ray's binary truth stands.
    if (!(static_cast<float>(m.near_mm) < v && static_cast<float>(m.far_mm) >= v)) continue;
    f.truth.data()[m.index] = 1.0F - m.near_coverage;
    std::copy(m.near_rgb.begin(), m.near_rgb.end(), f.true_foreground.data() + 3 * m.index);
  }
}

std::vector<EvalCase> sim_cases(const SimProtocolOptions& o) {
  Rig rig = sim::make_sim_rig(o.sim);
  const PinholeIntrinsics k = rig.calibration.rgb.intrinsics();
  // The service's virtual objects where the service puts them on this rig (its default
  // config: the demo scene and the ground receiver of differential rendering), so the matte
  // is scored on what the service mattes.
  const ServiceConfig config;
  std::vector<ObjectConfig> placed = config.objects;
  place_objects(placed, rig.scene);
  for (ObjectConfig& obj : placed) obj.position->z() += o.lift_m;
  std::vector<render::VirtualObject> objects =
      make_scene_objects(placed, config.ground, default_prt_cache_dir());
  const std::vector<render::VirtualObject> placeholders = placeholder_objects(objects);
  render::Renderer renderer(renderer_config_for(objects));
  render::RenderTarget lit, shown;
  lit.output = render::ColourOutput::LinearFloat;
  shown.output = render::ColourOutput::Display8;
  const auto min_mm = static_cast<std::uint16_t>(KinectNoiseParams{}.min_depth_m * 1000.0);

  EvalCase c;
  c.name = case_name(o);
  c.intrinsics = k;
  c.temporal_window = 8;  // Middlebury's K: the camera moves ~1 px a frame on tabletop
  std::shared_ptr<const Cubemap> light;
  RgbdFrame frame;
  for (int i = 0; i < o.frames; ++i) {
    if (rig.rgbd->read(frame, std::chrono::milliseconds(60000)) != ReadResult::Frame)
      throw std::runtime_error("sim protocol: the sim ended before frame " + std::to_string(i));
    if (!frame.truth || !frame.truth->rig_pose)
      throw std::runtime_error("sim protocol: a sim frame without truth");
    const FrameTruth& truth = *frame.truth;
    if (truth.light && truth.light != light) {
      // The environment only shades; the depth, which the matte needs, is the meshes'.
      light = truth.light;
      auto env = std::make_shared<const render::Environment>(render::make_environment(*light));
      for (auto& obj : objects)
        if (obj.material.shading != render::Material::Shading::Lambert) obj.environment = env;
    }
    const Pose T_world_camera = *truth.rig_pose * rig.calibration.T_rig_rgb;
    renderer.render({k, T_world_camera}, objects, lit);
    renderer.render({k, T_world_camera}, placeholders, shown);

    EvalFrame f;
    f.colour = frame.colour;
    f.real_depth_mm = frame.depth;
    f.virtual_depth_mm = lit.depth_mm;
    f.T_world_camera = T_world_camera;
    f.virtual_colour = shown.colour;
    const int w = f.colour.width(), h = f.colour.height();
    f.truth = ImageF(w, h);
    f.mask = ImageGray8(w, h);
    ImageGray8 contact(w, h), near(w, h);
    bool any_near = false;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float v = f.virtual_depth_mm.at(x, y);
        if (!(v > 0)) continue;
        const std::uint16_t real = truth.clean_depth.at(x, y);
        if (!real) continue;  // the sim's room is closed: never, but not evaluated if so
        f.mask.at(x, y) = 255;
        f.truth.at(x, y) = static_cast<float>(real) >= v ? 1.0F : 0.0F;  // ties: visible
        contact.at(x, y) = std::fabs(static_cast<double>(real) - v) <= o.contact_mm ? 1 : 0;
        if (real < min_mm) near.at(x, y) = 1, any_near = true;
      }
    apply_mixed_pixels(truth.mixed_pixels, f);
    f.contact_band = dilate_mask(contact, o.band_px);
    for (std::size_t p = 0; p < f.mask.pixel_count(); ++p)
      if (!f.mask.data()[p]) f.contact_band.data()[p] = 0;
    if (o.sim.near_occluder) {
      f.near_band = any_near ? dilate_mask(near, o.band_px) : ImageGray8(w, h);
      for (std::size_t p = 0; p < f.mask.pixel_count(); ++p)
        if (!f.mask.data()[p]) f.near_band.data()[p] = 0;
    }
    c.frames.push_back(std::move(f));
  }
  spdlog::info("eval: {}: {} frames rendered", c.name, c.frames.size());
  return {std::move(c)};
}

}  // namespace probeless::eval
