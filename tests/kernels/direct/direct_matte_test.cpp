#include "kernels/occlusion/baselines/direct_matte.hpp"

#include <gtest/gtest.h>

#include <random>

#include "kernels/occlusion/baselines/direct_matte_reference.hpp"
#include "support/cl_context.hpp"

namespace probeless::occlusion {
namespace {

using testing::cl_context;

// Depths that exercise every branch: unknown real depth, no virtual object, ties, and real
// surfaces on both sides of the object.
struct Scene {
  ImageRGB8 colour;
  DepthImage real;
  ImageF virt;
};

Scene random_scene(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> depth(400, 4000), pick(0, 9);
  Scene s{ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h)};
  for (auto& v : s.colour.elements()) v = static_cast<std::uint8_t>(depth(rng));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int r = depth(rng);
      s.real.at(x, y) = pick(rng) == 0 ? 0 : static_cast<std::uint16_t>(r);
      const int p = pick(rng);
      s.virt.at(x, y) = p < 3    ? 0.0F
                        : p == 3 ? static_cast<float>(r)
                                 : static_cast<float>(depth(rng)) + 0.25F;
    }
  return s;
}

class DirectMatteTest : public ::testing::TestWithParam<UnknownDepth> {};

TEST_P(DirectMatteTest, MatchesTheReferenceOnEverySize) {
  auto& ctx = cl_context();
  DirectMatte method(ctx, GetParam());
  DeviceImage<float, 1> alpha;  // resized by process()
  unsigned seed = 1;
  for (const auto& [w, h] : testing::kernel_test_sizes()) {
    const auto scene = random_scene(w, h, seed++);
    const DeviceImage<std::uint8_t, 3> colour(ctx, scene.colour);
    const DeviceImage<std::uint16_t, 1> real(ctx, scene.real);
    const DeviceImage<float, 1> virt(ctx, scene.virt);
    method.process({&colour, &real, &virt}, alpha);
    const auto expected = direct_matte_reference(scene.real, scene.virt, GetParam());
    EXPECT_EQ(alpha.download(ctx.queue()), expected) << w << "x" << h;
  }
}

INSTANTIATE_TEST_SUITE_P(Both, DirectMatteTest,
                         ::testing::Values(UnknownDepth::Occluded, UnknownDepth::Visible),
                         [](const auto& param_info) {
                           return std::string(
                               param_info.param == UnknownDepth::Visible ? "Direct2" : "Direct1");
                         });

TEST(DirectMatte, NamesFollowTheThesis) {
  EXPECT_EQ(DirectMatte(cl_context(), UnknownDepth::Occluded).name(), "direct1");
  EXPECT_EQ(DirectMatte(cl_context(), UnknownDepth::Visible).name(), "direct2");
}

TEST(DirectMatteReference, Cases) {
  using U = UnknownDepth;
  EXPECT_EQ(direct_alpha(1000, 0.0F, U::Visible), 0.0F);     // no object
  EXPECT_EQ(direct_alpha(0, 0.0F, U::Visible), 0.0F);        // no object, unknown depth
  EXPECT_EQ(direct_alpha(0, 900.0F, U::Occluded), 0.0F);     // Direct1
  EXPECT_EQ(direct_alpha(0, 900.0F, U::Visible), 1.0F);      // Direct2
  EXPECT_EQ(direct_alpha(1000, 900.0F, U::Occluded), 1.0F);  // real behind: visible
  EXPECT_EQ(direct_alpha(800, 900.0F, U::Visible), 0.0F);    // real in front: hidden
  EXPECT_EQ(direct_alpha(900, 900.0F, U::Occluded), 1.0F);   // tie: visible
}

TEST(DirectMatte, RejectsMismatchedInputs) {
  auto& ctx = cl_context();
  DirectMatte method(ctx, UnknownDepth::Occluded);
  const DeviceImage<std::uint8_t, 3> colour(ctx, 4, 4);
  const DeviceImage<std::uint16_t, 1> real(ctx, 4, 3);
  const DeviceImage<float, 1> virt(ctx, 4, 4);
  DeviceImage<float, 1> alpha;
  EXPECT_THROW(method.process({&colour, &real, &virt}, alpha), std::invalid_argument);
  EXPECT_THROW(method.process({&colour, nullptr, &virt}, alpha), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::occlusion
