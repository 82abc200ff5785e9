#pragma once
// CPU references for the material tests: an analytic sphere seen through the renderer's
// pinhole (ray-sphere intersection per pixel gives the exact normal and view ray), analytic
// environments, and the comparison of a rendered HDR image with a per-pixel reference. The
// "golden images" of these tests are computed here rather than stored.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "app/render/renderer.hpp"
#include "drivers/io/png.hpp"

namespace probeless::render::testing {

struct Hit {
  Eigen::Vector3d normal;  // world, unit
  Eigen::Vector3d view;    // camera -> surface, world, unit
};

// A sphere of radius `radius` at `centre`, seen from `eye` looking at the centre, image up
// towards world +z: the top of the picture shows the top of the sphere.
struct SphereView {
  PinholeIntrinsics k;
  Eigen::Vector3d eye{-0.45, 0.0, 0.0};
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0.1;

  SphereView() {
    k.width = 240;
    k.height = 180;
    k.fx = k.fy = 220;
    k.cx = 119.5;
    k.cy = 89.5;
  }
  Camera camera() const { return {k, camera_look_at(eye, centre)}; }
  VirtualObject object(const Material& material, std::shared_ptr<const Environment> env,
                       int segments = 128) const {
    VirtualObject o;
    o.mesh = std::make_shared<const Mesh>(
        make_sphere(static_cast<float>(radius), segments, segments / 2));
    o.T_world_object.translation = centre;
    o.material = material;
    o.environment = std::move(env);
    return o;
  }
  std::optional<Hit> trace(int x, int y) const {
    const Eigen::Matrix3d r = camera().T_world_camera.rotation.toRotationMatrix();
    const Eigen::Vector3d d =
        (r * Eigen::Vector3d((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0)).normalized();
    const Eigen::Vector3d oc = eye - centre;
    const double b = oc.dot(d), c = oc.squaredNorm() - radius * radius, disc = b * b - c;
    if (disc < 0) return std::nullopt;
    const Eigen::Vector3d p = eye + (-b - std::sqrt(disc)) * d;
    return Hit{(p - centre).normalized(), d};
  }
};

template <typename F>  // F: unit direction -> Eigen::Vector3d radiance
Cubemap cubemap_of(int n, F f) {
  Cubemap cube(n);
  for (int face = 0; face < 6; ++face)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const Eigen::Vector3d v =
            f(cube_direction(static_cast<CubeFace>(face), (x + 0.5) / n, (y + 0.5) / n));
        for (int c = 0; c < 3; ++c)
          cube.faces[static_cast<std::size_t>(face)].at(x, y, c) = static_cast<float>(v[c]);
      }
  return cube;
}

template <typename F>
std::shared_ptr<const Environment> environment_of(int n, F f) {
  return std::make_shared<const Environment>(make_environment(cubemap_of(n, f)));
}

inline Eigen::Vector3d rgb(const ImageRGBAF& img, int x, int y) {
  return {img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)};
}

struct Comparison {
  int pixels = 0;
  double max_error = 0, mean_error = 0;  // of |rendered - reference| per channel
  double reference_peak = 0;
};

// Compares the rendered radiance with reference(hit) on the pixels whose analytic ray meets
// the sphere at n.(-v) > min_cos (the tessellated silhouette is a little inside the true
// one, and normals there are the least accurate). Uncovered pixels inside count as errors.
// On failure (max_error > tolerance) writes both pictures, tone-mapped, to the test temp dir.
inline Comparison compare_sphere(const SphereView& view, const ImageRGBAF& rendered,
                                 const std::function<Eigen::Vector3d(const Hit&)>& reference,
                                 double tolerance, const std::string& name, double min_cos = 0.2) {
  Comparison c;
  ImageRGB8 got(rendered.width(), rendered.height()), want(rendered.width(), rendered.height());
  for (int y = 0; y < rendered.height(); ++y)
    for (int x = 0; x < rendered.width(); ++x) {
      const std::optional<Hit> hit = view.trace(x, y);
      if (!hit || hit->normal.dot(-hit->view) <= min_cos) continue;
      const Eigen::Vector3d expected = reference(*hit);
      const Eigen::Vector3d actual = rgb(rendered, x, y);
      const double error = rendered.at(x, y, 3) != 1.f ? std::numeric_limits<double>::infinity()
                                                       : (actual - expected).cwiseAbs().maxCoeff();
      c.max_error = std::max(c.max_error, error);
      c.mean_error += std::isfinite(error) ? error : 1e9;
      c.reference_peak = std::max(c.reference_peak, expected.maxCoeff());
      ++c.pixels;
      for (int ch = 0; ch < 3; ++ch) {
        got.at(x, y, ch) = static_cast<std::uint8_t>(std::clamp(actual[ch] * 128.0, 0.0, 255.0));
        want.at(x, y, ch) = static_cast<std::uint8_t>(std::clamp(expected[ch] * 128.0, 0.0, 255.0));
      }
    }
  if (c.pixels > 0) c.mean_error /= c.pixels;
  EXPECT_GT(c.pixels, 1000) << name;
  EXPECT_LE(c.max_error, tolerance) << name << ": mean error " << c.mean_error << " over "
                                    << c.pixels << " pixels, reference peak " << c.reference_peak;
  if (!(c.max_error <= tolerance)) {
    write_png(::testing::TempDir() + name + "_actual.png", got);
    write_png(::testing::TempDir() + name + "_expected.png", want);
    ADD_FAILURE() << name << ": pictures (radiance x 128) in " << ::testing::TempDir();
  }
  ::testing::Test::RecordProperty(name + "_max_error", std::to_string(c.max_error));
  return c;
}

// One renderer (one EGL context) per suite, made on the test thread; tests skip without EGL.
class MaterialFixture : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    try {
      renderer_ = std::make_unique<Renderer>();
    } catch (const std::exception& e) {
      skip_reason_ = e.what();
    }
  }
  static void TearDownTestSuite() { renderer_.reset(); }
  void SetUp() override {
    if (!renderer_) GTEST_SKIP() << "no headless EGL/GLES 3 context: " << skip_reason_;
  }
  static Renderer& renderer() { return *renderer_; }
  // The objects seen from `view`'s camera, as linear radiance.
  static ImageRGBAF render(const SphereView& view, const std::vector<VirtualObject>& objects) {
    RenderTarget out;
    out.output = ColourOutput::LinearFloat;
    renderer_->render(view.camera(), objects, out);
    return out.radiance;
  }
  // The sphere of `view` in `material` under `env`.
  static ImageRGBAF render(const SphereView& view, const Material& material,
                           std::shared_ptr<const Environment> env, int segments = 128) {
    return render(view, {view.object(material, std::move(env), segments)});
  }
  static Material material(Material::Shading shading,
                           Eigen::Vector3f colour = Eigen::Vector3f::Ones()) {
    Material m;
    m.shading = shading;
    m.base_colour = Eigen::Vector4f(colour.x(), colour.y(), colour.z(), 1.f);
    return m;
  }

 private:
  static inline std::unique_ptr<Renderer> renderer_;
  static inline std::string skip_reason_;
};

}  // namespace probeless::render::testing
