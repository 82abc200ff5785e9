// Issue #19 item 6: a virtual box standing on a real table neither sinks into it nor floats.
// A camera pitched 35 degrees down at a textured table (the real scene, through the Kinect
// noise model of core/depth_noise.hpp), a 15 cm virtual box on it at 0.8, 1.5 and 2.5 m; the
// true matte is 1 on the whole box (the table is behind it everywhere). Matte MSE in the 10 px
// band around the box's contact line, for every method the service offers.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "core/depth_noise.hpp"
#include "kernels/occlusion/baselines/direct_matte_reference.hpp"
#include "kernels/occlusion/method_registry.hpp"
#include "support/cl_context.hpp"

namespace probeless::occlusion {
namespace {

using testing::cl_context;

struct ContactScene {
  ImageRGB8 colour;
  ImageF virt;
  DepthImage clean;
  Image<std::uint8_t, 1> band;  // 1 on the box within 10 px of its contact line
  int band_pixels = 0;
};

ContactScene contact_scene(double distance_m) {
  const int w = 320, h = 240;
  const double f = 525.0 * w / 640, cx = w / 2.0, cy = h / 2.0;
  const double th = 35.0 * M_PI / 180, ct = std::cos(th), st = std::sin(th);
  const double height = distance_m * st;  // the optical axis meets the table at distance_m
  const std::array<double, 3> up{0, -ct, -st}, e1{1, 0, 0}, e3{0, -st, ct};  // e3 = e1 x up
  const std::array<double, 3> base{0, 0, distance_m};  // the axis's table point
  const double half = 0.075, size = 0.15;
  std::mt19937 rng(3);
  std::normal_distribution<float> grain(0.0F, 5.0F);
  ContactScene s{ImageRGB8(w, h), ImageF(w, h), DepthImage(w, h), Image<std::uint8_t, 1>(w, h)};
  Image<std::uint8_t, 1> contact(w, h);
  const auto dot = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::array<double, 3> d{(x - cx) / f, (y - cy) / f, 1.0};  // z = 1: t is the depth
      const double denom = ct * d[1] + st * d[2];
      const double table = denom > 0 ? height / denom : 0;
      // The box in its own frame (e1, up, e3) about `base`: slabs.
      const std::array<double, 3> o{-dot(base, e1), -dot(base, up), -dot(base, e3)};
      const std::array<double, 3> dl{dot(d, e1), dot(d, up), dot(d, e3)};
      const std::array<double, 3> lo{-half, 0, -half}, hi{half, size, half};
      double t0 = 0, t1 = 1e9;
      for (int k = 0; k < 3; ++k) {
        double a = (lo[k] - o[k]) / dl[k], b = (hi[k] - o[k]) / dl[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a), t1 = std::min(t1, b);
      }
      const bool box = t0 < t1 && t0 > 0;
      s.virt.at(x, y) = box ? static_cast<float>(t0 * 1000) : 0.0F;
      // The contact line: hits within a pixel's footprint of the table.
      if (box) contact.at(x, y) = o[1] + t0 * dl[1] < 1.5 * t0 / f;
      s.clean.at(x, y) = table > 0 && table < 6 ? std::uint16_t(std::lround(table * 1000)) : 0;
      const double u = x * 0.02 + std::sin(y * 0.15);  // wood grain
      const float base_c[3] = {float(150 + 20 * std::sin(u)), float(105 + 15 * std::sin(u)), 70};
      for (int c = 0; c < 3; ++c)
        s.colour.at(x, y, c) = std::uint8_t(std::clamp(base_c[c] + grain(rng), 0.0F, 255.0F));
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!(s.virt.at(x, y) > 0)) continue;
      bool near = false;
      for (int yy = std::max(0, y - 10); yy <= std::min(h - 1, y + 10) && !near; ++yy)
        for (int xx = std::max(0, x - 10); xx <= std::min(w - 1, x + 10) && !near; ++xx)
          near = contact.at(xx, yy) != 0;
      s.band.at(x, y) = near;
      s.band_pixels += near;
    }
  return s;
}

// Contact-band MSE of `method` over `frames` noise draws (the truth is 1 on the box).
double contact_mse(const ContactScene& s, const std::string& method, int frames) {
  auto& ctx = cl_context();
  auto m = make_method(ctx, method);
  const DeviceImageRGB8 colour(ctx, s.colour);
  const DeviceImageF virt(ctx, s.virt);
  DeviceImageF alpha;
  double sum = 0;
  for (int k = 0; k < frames; ++k) {
    const auto depth = apply_kinect_noise(s.clean, 525.0 * 320 / 640, 100 + k);
    const DeviceImage<std::uint16_t, 1> real(ctx, depth);
    m->process({&colour, &real, &virt}, alpha);
    const auto a = alpha.download(ctx.queue());
    for (int y = 0; y < s.band.height(); ++y)
      for (int x = 0; x < s.band.width(); ++x)
        if (s.band.at(x, y)) sum += (1.0 - a.at(x, y)) * (1.0 - a.at(x, y));
  }
  return sum / (double(frames) * s.band_pixels);
}

// The per-pixel tolerance with k sigma of the Kinect model is k sigma_z(v) of core/depth_noise.
TEST(Contact, NoiseModelToleranceIsKSigma) {
  for (const float k : {3.0F, 4.0F}) {
    CategoriseParams p;
    p.depth_tolerance_mm = 1.2F * k;
    p.tolerance_per_mm = 0.0019e-3F * k;
    p.tolerance_z0_mm = 400.0F;
    for (const float v : {500.0F, 800.0F, 1500.0F, 2500.0F, 4000.0F})
      EXPECT_NEAR(depth_tolerance_mm(p, v), k * 1000.0 * kinect_axial_sigma_m(v / 1000.0), 1e-3)
          << k << " " << v;
  }
  CategoriseParams fixed;  // the default: 15 mm at every depth
  EXPECT_EQ(depth_tolerance_mm(fixed, 700.0F), 15.0F);
  EXPECT_EQ(depth_tolerance_mm(fixed, 3000.0F), 15.0F);
}

// Direct counts a real surface within the tolerance in front as visible, beyond it as hidden.
TEST(Contact, DirectTakesTheTolerance) {
  EXPECT_EQ(direct_alpha(990, 1000.0F, UnknownDepth::Occluded, 15.0F), 1.0F);
  EXPECT_EQ(direct_alpha(985, 1000.0F, UnknownDepth::Occluded, 15.0F), 1.0F);  // on the limit
  EXPECT_EQ(direct_alpha(984, 1000.0F, UnknownDepth::Occluded, 15.0F), 0.0F);
  EXPECT_EQ(direct_alpha(990, 1000.0F, UnknownDepth::Occluded), 0.0F);  // no tolerance
  CategoriseParams p;
  p.depth_tolerance_mm = 5.0F;
  DepthImage real(3, 1);
  ImageF virt(3, 1);
  real.at(0, 0) = 996, real.at(1, 0) = 994, real.at(2, 0) = 0;
  for (auto& v : virt.elements()) v = 1000.0F;
  auto& ctx = cl_context();
  DirectMatte direct(ctx, UnknownDepth::Occluded, p);
  const DeviceImageRGB8 colour(ctx, ImageRGB8(3, 1));
  const DeviceImage<std::uint16_t, 1> dr(ctx, real);
  const DeviceImageF dv(ctx, virt);
  DeviceImageF alpha;
  direct.process({&colour, &dr, &dv}, alpha);
  const auto a = alpha.download(ctx.queue());
  EXPECT_EQ(a.at(0, 0), 1.0F);
  EXPECT_EQ(a.at(1, 0), 0.0F);
  EXPECT_EQ(a.at(2, 0), 0.0F);
  EXPECT_EQ(a, direct_matte_reference(real, virt, UnknownDepth::Occluded, p));
}

TEST(Contact, BoxOnTableNeitherSinksNorFloats) {
  std::map<std::string, double> worst;
  for (const double d : {0.8, 1.5, 2.5}) {
    const auto s = contact_scene(d);
    ASSERT_GT(s.band_pixels, 100) << d;
    for (const auto& method : method_names()) {
      const double e = contact_mse(s, method, 4);
      std::printf("contact MSE x1e3 at %.1f m  %-12s %8.2f\n", d, method.c_str(), 1e3 * e);
      worst[method] = std::max(worst[method], e);
    }
  }
  // The methods that decide by the depth test and colour (CVF, Bilateral) and Direct, which
  // now shares CVF's tolerance (without it: 31e-3, 4e-3 and 52e-3 at 0.8, 1.5 and 2.5 m): the
  // box's contact band is not hidden by the table's depth noise. Guided (0.5 on every
  // undecided pixel, by its definition), Crabb and the soft ramps (their own published
  // thresholds) are printed, not held to it.
  for (const char* m : {"cvf", "cvf_thesis", "direct1", "direct2", "bilateral"})
    EXPECT_LT(worst[m], 0.002) << m;
}

}  // namespace
}  // namespace probeless::occlusion
