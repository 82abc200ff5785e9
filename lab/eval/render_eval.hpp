#pragma once
// `probeless eval render --source sim` (issue #6; docs/rendering.md "eval render"): the
// service's own light stage (LightCapture) runs on the sim's slow orbit, and the virtual
// objects are rendered from its snapshots and from the sim's ground-truth light; the report
// compares the two renders (object pixels, the ground shadow, a chrome sphere) and times how
// fast the objects follow a lamp switch.
#include <optional>
#include <string>
#include <vector>

#include "app/pipeline/service_config.hpp"
#include "app/render/environment.hpp"

namespace probeless::eval {

struct RenderEvalOptions {
  // Sim time the rig orbits before the comparison (the issue's "once the rig has orbited for
  // 2 s"). The run starts this long before the sim's lamp switch (world time 6 s, lamp B off),
  // so the comparison is the light just before the switch.
  double orbit_s = 2.0;
  double after_switch_s = 1.5;  // how long the lamp response is followed
  std::string sim_spec;         // extra sim options (seed=2,fisheye_size=1024,...)
  // The service's configuration: objects, ground, [light]; its source must be the sim.
  ServiceConfig config;
  // The truth environment: the sim's room rendered from the objects' light point with
  // `truth_supersample`^2 rays per texel at the keyframe's face size.
  int truth_supersample = 2;
  int sphere_image_size = 256;  // the chrome-sphere renders, square
  // Non-empty: write chrome_sphere.png (captured | truth | |difference| x4) and objects.png
  // (captured | truth) there.
  std::string dump_dir;
};

struct LampSample {
  double t_s = 0;        // snapshot time, world seconds
  double captured = 0;   // mean radiance (luminance) of the diffuse objects' pixels
  double truth = 0;      // the same under the truth light of that moment
  double rel_error = 0;  // |captured - truth| / truth
};

struct RenderEvalReport {
  int fisheye_frames = 0;
  int snapshots = 0;
  double compare_t_s = 0;  // world time of the snapshot compared (the last before the switch)
  // sqrt(sum |captured - truth|^2 / sum |truth|^2) over RGB of the pixels the objects cover
  double object_rel_error = 0;
  int object_pixels = 0;
  // The same over the ground shadow's pixels: where the truth render's signed radiance change
  // on the real ground is at least 10 % of its largest magnitude
  double shadow_rel_error = 0;
  int shadow_pixels = 0;
  double shadow_mean_captured = 0, shadow_mean_truth = 0;  // mean change (luminance)
  double sphere_rel_rmse = 0;                              // the chrome sphere, over its pixels
  // The same over the sphere image's upper and lower halves (each relative to its own truth):
  // roughly what lies above and below the light point's horizon.
  double sphere_rel_rmse_upper = 0, sphere_rel_rmse_lower = 0;
  int sphere_pixels = 0;
  // Lamp switch: world time of the switch, the samples around it, and the time from the
  // switch to the first snapshot from which on every snapshot is within 10 % of the truth;
  // empty when that never happened within after_switch_s.
  double switch_t_s = 0;
  std::vector<LampSample> lamp;
  std::optional<double> lamp_response_s;
  double lamp_rel_error_before = 0;  // the last sample before the switch
  double lamp_rel_error_final = 0;   // the last sample
  double truth_drop = 0;             // truth after / before: how big the switch is
};

// Throws std::invalid_argument for options it cannot run (not the sim, no objects, no light)
// and std::runtime_error when a stage fails (the message says which).
RenderEvalReport evaluate_render_sim(const RenderEvalOptions& options);

// The relative error of two float renders over a pixel mask (RGB): sqrt(sum |a - b|^2 /
// sum |b|^2); 0 for an empty mask.
double relative_rgb_error(const render::ImageRGBAF& a, const render::ImageRGBAF& b,
                          const std::vector<bool>& mask);

}  // namespace probeless::eval
