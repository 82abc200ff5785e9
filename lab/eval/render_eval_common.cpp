#include "lab/eval/render_eval_common.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/exposure_count.hpp"
#include "drivers/io/png.hpp"
#include "kernels/envmap/envmap_types.hpp"
#include "lab/eval/light_eval.hpp"

namespace probeless::eval {

using render::ImageRGBAF;

double luminance(const ImageRGBAF& img, int x, int y) {
  return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
}

std::shared_ptr<const render::Environment> scaled_environment(const LightSnapshot& snap,
                                                              double scale) {
  ImageRGBAF faces = snap.texels;
  for (int y = 0; y < faces.height(); ++y)
    for (int x = 0; x < faces.width(); ++x)
      for (int c = 0; c < 3; ++c) faces.at(x, y, c) *= static_cast<float>(scale);
  ShRgb sh = snap.sh;
  for (auto& c : sh.c) c *= scale;
  return std::make_shared<const render::Environment>(render::make_environment(faces, sh));
}

std::shared_ptr<const render::Environment> truth_environment(
    const std::shared_ptr<const sim::SimWorld>& world, const Eigen::Vector3d& where, int lamps,
    int n, int s, const sim::Occluder* objects,
    std::shared_ptr<const render::Environment>* object_share) {
  std::vector<bool> observed;
  envmap::ImageRGBAF hits;
  const ImageRGBAF fine = light::render_truth_cubemap(world, where, lamps, n * s, objects,
                                                      object_share ? &hits : nullptr);
  const ImageRGBAF texels = light::average_observed(fine, n, observed);
  if (object_share)
    *object_share = std::make_shared<const render::Environment>(
        render::make_environment(envmap::to_cubemap(light::average_observed(hits, n, observed))));
  return std::make_shared<const render::Environment>(
      render::make_environment(envmap::to_cubemap(texels)));
}

std::vector<render::VirtualObject> lit_by(std::vector<render::VirtualObject> objects,
                                          const std::shared_ptr<const render::Environment>& env) {
  for (auto& o : objects) o.environment = env;
  return objects;
}

ImageRGBAF render_float(render::Renderer& renderer, const render::Camera& camera,
                        const std::vector<render::VirtualObject>& objects) {
  render::RenderTarget target;
  target.output = render::ColourOutput::LinearFloat;
  renderer.render(camera, objects, target);
  return target.radiance;
}

render::VirtualObject chrome_sphere(const Eigen::Vector3d& centre) {
  render::VirtualObject ball;
  ball.mesh = std::make_shared<const render::Mesh>(render::make_sphere(kSphereRadius, 96, 48));
  ball.T_world_object.translation = centre;
  ball.material.shading = render::Material::Shading::Mirror;
  return ball;
}

render::Camera sphere_camera(const Eigen::Vector3d& target, const Eigen::Vector3d& from, int size) {
  Eigen::Vector3d dir = from - target;
  dir.z() = 0;
  if (dir.norm() < 1e-6) dir = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d eye = target + kSphereDistance * dir.normalized();
  PinholeIntrinsics k;
  k.width = k.height = size;
  const double half_angle = std::asin(kSphereRadius / kSphereDistance);
  k.fx = k.fy = 0.85 * 0.5 * size / std::tan(half_angle);
  k.cx = k.cy = 0.5 * (size - 1);
  return {k, render::camera_look_at(eye, target)};
}

void write_panels(const std::string& path, const ImageRGBAF& a, const ImageRGBAF& b,
                  const std::vector<bool>& mask, bool difference) {
  std::vector<double> lum;
  for (int y = 0; y < b.height(); ++y)
    for (int x = 0; x < b.width(); ++x)
      if (mask[static_cast<std::size_t>(y * b.width() + x)]) lum.push_back(luminance(b, x, y));
  double exposure = 1;
  if (!lum.empty()) {
    std::nth_element(lum.begin(), lum.begin() + lum.size() / 2, lum.end());
    if (lum[lum.size() / 2] > 0) exposure = 0.18 / lum[lum.size() / 2];
  }
  const int w = a.width(), h = a.height(), panels = difference ? 3 : 2, gap = 4;
  ImageRGB8 out(panels * w + (panels - 1) * gap, h);
  const auto put = [&](int px, int x, int y, double v, int c) {
    const double g = std::pow(std::clamp(v * exposure, 0.0, 1.0), 1.0 / 2.2);
    out.at(px * (w + gap) + x, y, c) = static_cast<std::uint8_t>(std::lround(255.0 * g));
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        put(0, x, y, a.at(x, y, c), c);
        put(1, x, y, b.at(x, y, c), c);
        if (difference) put(2, x, y, 4.0 * std::abs(a.at(x, y, c) - b.at(x, y, c)), c);
      }
  write_png(path, out);
}

namespace {
constexpr std::chrono::milliseconds kSimTimeout{5000};
}  // namespace

namespace {
[[noreturn]] void throw_capture_failed(const LightCapture& capture) {
  throw std::runtime_error("eval render: light capture: " +
                           capture.status().value("error", std::string("failed")));
}
}  // namespace

void initialise_or_throw(LightCapture& capture) {
  if (!capture.initialise()) throw_capture_failed(capture);
}

void SimLightFeed::read_fisheye() {
  rig_.fisheye->set_next_exposure(sequencer_.next());
  if (rig_.fisheye->read(fisheye_, kSimTimeout) != ReadResult::Frame)
    throw std::runtime_error("eval render: the sim's fisheye stopped");
}

bool SimLightFeed::next_rgbd() {
  if (rgbd_ended_ || rgbd_.timestamp_ns > fisheye_.timestamp_ns) return false;
  if (rig_.rgbd->read(rgbd_, kSimTimeout) != ReadResult::Frame || !rgbd_.truth ||
      !rgbd_.truth->rig_pose) {
    rgbd_ended_ = true;
    return false;
  }
  capture_.add_rig_pose(rgbd_.timestamp_ns, *rgbd_.truth->rig_pose);
  capture_.offer_rgbd(rgbd_);
  return true;
}

void SimLightFeed::update_light() {
  sequencer_.observe(fisheye_.exposure,
                     count_exposure(fisheye_.raw, fisheye_.bit_depth, fisheye_.black_level));
  if (capture_.admit(fisheye_) && !capture_.process(fisheye_)) throw_capture_failed(capture_);
}

}  // namespace probeless::eval
