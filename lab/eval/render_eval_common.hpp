#pragma once
// What `eval render`'s two protocols share (docs/rendering.md "eval render", docs/fusion.md):
// the captured light as the renderer takes it, the sim's truth environment, and the chrome
// sphere the environments are compared on (thesis Fig. 4.13 / 6.9).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "app/pipeline/light_capture.hpp"
#include "app/render/renderer.hpp"
#include "drivers/bracket/bracket_sequencer.hpp"
#include "drivers/sim/sim_world.hpp"
#include "drivers/source.hpp"

namespace probeless::eval {

// The chrome sphere: the size of the default scene's mirror sphere, seen from 0.6 m.
inline constexpr float kSphereRadius = 0.1f;
inline constexpr double kSphereDistance = 0.6;

double luminance(const render::ImageRGBAF& img, int x, int y);

// A snapshot's texels and SH times `scale` (sim radiance per unit of the light stage's).
std::shared_ptr<const render::Environment> scaled_environment(const LightSnapshot& snap,
                                                              double scale);

// The sim's room from `where` at face size n, s x s rays per texel (box-averaged). With
// `objects` they are in it, and `object_share` (when given) becomes an environment whose
// radiance is each texel's share of rays that meet them first (0..1, grey).
std::shared_ptr<const render::Environment> truth_environment(
    const std::shared_ptr<const sim::SimWorld>& world, const Eigen::Vector3d& where, int lamps,
    int n, int s, const sim::Occluder* objects = nullptr,
    std::shared_ptr<const render::Environment>* object_share = nullptr);

std::vector<render::VirtualObject> lit_by(std::vector<render::VirtualObject> objects,
                                          const std::shared_ptr<const render::Environment>& env);

render::ImageRGBAF render_float(render::Renderer& renderer, const render::Camera& camera,
                                const std::vector<render::VirtualObject>& objects);

// A mirror ball of kSphereRadius at `centre`.
render::VirtualObject chrome_sphere(const Eigen::Vector3d& centre);

// A camera looking at `target` horizontally from the side of `from`, framing the sphere in
// about 85 % of the image.
render::Camera sphere_camera(const Eigen::Vector3d& target, const Eigen::Vector3d& from, int size);

// capture.initialise(), or std::runtime_error naming why it failed.
void initialise_or_throw(LightCapture& capture);

// The sim's light capture fed as the service feeds it, one fisheye frame a step: the bracket's
// next exposure, the fisheye frame, every colour frame up to its time (its rig pose and colour
// into the capture, then to `on_rgbd`), the exposure count, the light update. Throws
// std::runtime_error when a source stops or the capture fails.
class SimLightFeed {
 public:
  SimLightFeed(Rig& rig, LightCapture& capture) : rig_(rig), capture_(capture) {}
  template <typename OnRgbd>
  void step(OnRgbd&& on_rgbd) {
    read_fisheye();
    while (next_rgbd()) on_rgbd(rgbd_);
    update_light();
  }

 private:
  void read_fisheye();
  bool next_rgbd();  // the next colour frame up to the fisheye frame's time, fed to the capture
  void update_light();

  Rig& rig_;
  LightCapture& capture_;
  BracketSequencer sequencer_;
  RgbdFrame rgbd_;
  FisheyeFrame fisheye_;
  bool rgbd_ended_ = false;
};

// Side by side, one exposure for all (mid grey at the truth's median over `mask`), gamma 2.2;
// with `difference`, a third panel |a - b| x 4.
void write_panels(const std::string& path, const render::ImageRGBAF& a, const render::ImageRGBAF& b,
                  const std::vector<bool>& mask, bool difference);

}  // namespace probeless::eval
