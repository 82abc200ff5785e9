// The baselines' OpenCL kernels against their CPU references on random scenes and sizes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/occlusion/baselines/bilateral_matte.hpp"
#include "kernels/occlusion/baselines/crabb_matte.hpp"
#include "kernels/occlusion/baselines/crabb_matte_reference.hpp"
#include "kernels/occlusion/baselines/guided_matte.hpp"
#include "kernels/occlusion/baselines/meta_soft_matte.hpp"
#include "kernels/occlusion/baselines/soft_ramp_matte.hpp"

namespace probeless::occlusion {
namespace {

ComputeContext& context() {
  static ComputeContext ctx;
  return ctx;
}

struct Scene {
  ImageRGB8 colour;
  DepthImage depth;
  ImageF virt;
};

Scene random_scene(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  Scene s{ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h)};
  const float cx = w * u(rng), cy = h * u(rng), r = 0.3F * std::min(w, h) + 2;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool fg = std::hypot(x - cx, y - cy) < r;
      for (int c = 0; c < 3; ++c)
        s.colour.at(x, y, c) = std::uint8_t((fg ? 180 : 60) + 60 * u(rng) * (c + 1) / 3);
      const float z = fg ? 900.0F + 30.0F * u(rng) : 1100.0F + 40.0F * u(rng);
      s.depth.at(x, y) = u(rng) < 0.05F ? 0 : std::uint16_t(z);
      s.virt.at(x, y) = x > w / 5 ? 1000.0F + 0.5F * y : 0.0F;
    }
  return s;
}

template <typename Reference>
void expect_matches(OcclusionMethod& method, Reference&& reference, double tolerance) {
  const int sizes[][2] = {{1, 1}, {33, 17}, {64, 48}, {101, 37}};
  std::uint32_t seed = 1;
  for (const auto& sz : sizes) {
    const auto s = random_scene(sz[0], sz[1], seed++);
    DeviceImageRGB8 colour(context(), s.colour);
    DeviceDepthImage depth(context(), s.depth);
    DeviceImageF virt(context(), s.virt), alpha;
    method.process({&colour, &depth, &virt}, alpha);
    const auto got = alpha.download(context().queue());
    const ImageF want = reference(s);
    for (int y = 0; y < sz[1]; ++y)
      for (int x = 0; x < sz[0]; ++x)
        ASSERT_NEAR(got.at(x, y), want.at(x, y), tolerance)
            << method.name() << " " << sz[0] << "x" << sz[1] << " at " << x << "," << y;
  }
}

TEST(BaselinesDevice, Guided) {
  GuidedMatte m(context());
  expect_matches(
      m, [](const Scene& s) { return guided_matte_reference(s.colour, s.depth, s.virt); }, 2e-4);
}

TEST(BaselinesDevice, Bilateral) {
  BilateralMatte m(context());
  expect_matches(
      m, [](const Scene& s) { return bilateral_matte_reference(s.colour, s.depth, s.virt); }, 1e-4);
}

TEST(BaselinesDevice, Crabb) {
  CrabbMatte m(context());
  expect_matches(
      m, [](const Scene& s) { return crabb_matte_reference(s.depth, s.virt); }, 0.0);
}

TEST(BaselinesDevice, SoftRamp) {
  SoftRampMatte m(context());
  expect_matches(
      m, [](const Scene& s) { return soft_ramp_matte_reference(s.depth, s.virt); }, 1e-4);
}

TEST(BaselinesDevice, MetaSoft) {
  MetaSoftMatte m(context());
  expect_matches(
      m, [](const Scene& s) { return meta_soft_matte_reference(s.depth, s.virt); }, 1e-4);
}

}  // namespace
}  // namespace probeless::occlusion
