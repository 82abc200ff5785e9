#include "kernels/composite/compositor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "kernels/composite/composite_reference.hpp"
#include "support/cl_context.hpp"

namespace probeless {
namespace {

using testing::cl_context;

template <typename ImageT>
ImageT random_bytes(int w, int h, std::mt19937& rng) {
  ImageT image(w, h);
  std::uniform_int_distribution<int> d(0, 255);
  for (auto& v : image.elements()) v = static_cast<std::uint8_t>(d(rng));
  return image;
}

// Mattes as the stages produce them (0, 1, soft values) plus what they must never produce
// but the compositor must survive: out of range and NaN.
ImageF random_alpha(int w, int h, std::mt19937& rng) {
  const float specials[] = {0.0F,          1.0F,  0.5F,
                            -0.25F,        1.5F,  std::numeric_limits<float>::quiet_NaN(),
                            1.0F / 255.0F, 0.998F};
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  std::uniform_int_distribution<int> pick(0, 15);
  ImageF a(w, h);
  for (auto& v : a.elements()) {
    const int p = pick(rng);
    v = p < 8 ? specials[p] : u(rng);
  }
  return a;
}

TEST(Compositor, MatchesTheReferenceExactlyOnEverySize) {
  auto& ctx = cl_context();
  Compositor compositor(ctx);
  DeviceImageRGB8 out;
  DeviceImageGray8 matte;
  std::mt19937 rng(7);
  for (const auto& [w, h] : testing::kernel_test_sizes()) {
    const auto real = random_bytes<ImageRGB8>(w, h, rng);
    const auto virt = random_bytes<ImageRGBA8>(w, h, rng);
    const auto alpha = random_alpha(w, h, rng);
    const DeviceImageRGB8 d_real(ctx, real);
    const DeviceImageRGBA8 d_virt(ctx, virt);
    const DeviceImageF d_alpha(ctx, alpha);
    compositor.process(d_real, d_virt, d_alpha, out);
    compositor.matte8(d_alpha, matte);
    EXPECT_EQ(out.download(ctx.queue()), composite_reference(real, virt, alpha)) << w << "x" << h;
    EXPECT_EQ(matte.download(ctx.queue()), matte8_reference(alpha)) << w << "x" << h;
  }
}

TEST(CompositeReference, EndpointsAndRounding) {
  EXPECT_EQ(composite_channel(10, 200, 0.0F), 10);
  EXPECT_EQ(composite_channel(10, 200, 1.0F), 200);
  EXPECT_EQ(composite_channel(0, 255, 0.5F), 128);  // 127.5 rounds half up
  EXPECT_EQ(composite_channel(0, 3, 0.5F), 2);      // 1.5 -> 2
  EXPECT_EQ(composite_channel(255, 255, 0.3F), 255);
  EXPECT_EQ(composite_channel(10, 200, std::numeric_limits<float>::quiet_NaN()), 10);
  EXPECT_EQ(composite_channel(10, 200, -1.0F), 10);
  EXPECT_EQ(composite_channel(10, 200, 2.0F), 200);
  ImageF a(3, 1);
  a.at(0, 0) = 0.0F;
  a.at(1, 0) = 0.5F;
  a.at(2, 0) = 1.0F;
  const auto m = matte8_reference(a);
  EXPECT_EQ(m.at(0, 0), 0);
  EXPECT_EQ(m.at(1, 0), 128);
  EXPECT_EQ(m.at(2, 0), 255);
}

TEST(CompositeReference, StaysWithinOneLevelOfTheExactBlend) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> b(0, 255);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  for (int i = 0; i < 100000; ++i) {
    const int r = b(rng), v = b(rng);
    const float a = u(rng);
    const double exact = static_cast<double>(a) * v + (1.0 - a) * r;
    EXPECT_LE(
        std::abs(composite_channel(static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(v), a) -
                 exact),
        0.5 + 1e-3);
  }
}

TEST(Compositor, RejectsMismatchedSizes) {
  auto& ctx = cl_context();
  Compositor compositor(ctx);
  DeviceImageRGB8 real(ctx, 4, 4), out;
  DeviceImageRGBA8 virt(ctx, 4, 4);
  DeviceImageF alpha(ctx, 3, 4);
  EXPECT_THROW(compositor.process(real, virt, alpha, out), std::invalid_argument);
}

}  // namespace
}  // namespace probeless
