// The OpenCL CVF stage against its CPU reference on random sizes (odd widths included):
// the guided filter alone, then every intermediate of the whole method.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/occlusion/common/cvf_kernel_args.hpp"
#include "kernels/occlusion/common/guided_filter.hpp"
#include "kernels/occlusion/common/guided_filter_reference.hpp"
#include "kernels/occlusion/cvf/cvf_guided.hpp"
#include "kernels/occlusion/cvf/cvf_matte.hpp"
#include "kernels/occlusion/cvf/cvf_reference.hpp"

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

// Random blobs of colour and depth, holes in the depth, a virtual disc plus a slanted plane.
Scene random_scene(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  std::normal_distribution<float> n(0.0F, 8.0F);
  Scene s{ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h)};
  const float cx = w * u(rng), cy = h * u(rng), r = 0.3F * std::min(w, h) + 2;
  const float bx = w * u(rng), by = h * u(rng);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool fg = std::hypot(x - cx, y - cy) < r;
      const bool near_edge = std::fabs(std::hypot(x - cx, y - cy) - r) < 2.5F;
      const std::uint8_t base[3] = {std::uint8_t(fg ? 190 : 40), std::uint8_t(x * 255 / w),
                                    std::uint8_t(fg ? 50 : 170)};
      for (int c = 0; c < 3; ++c)
        s.colour.at(x, y, c) = std::uint8_t(std::clamp(base[c] + n(rng), 0.0F, 255.0F));
      const float z = fg ? 800.0F + 2.0F * (y - cy) : 2200.0F;
      s.depth.at(x, y) = near_edge || u(rng) < 0.02F ? 0 : std::uint16_t(z + n(rng));
      const bool on = (x > bx * 0.3F) || std::hypot(x - bx, y - by) < r;
      s.virt.at(x, y) = on ? 1200.0F + 3.0F * x : 0.0F;
    }
  return s;
}

template <typename T, int C>
Image<T, C> download(DeviceImage<T, C>& d) {
  return d.download(context().queue());
}

TEST(GuidedFilterDevice, MatchesReferenceOnRandomSizes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  const int sizes[][2] = {{1, 1}, {7, 5}, {63, 17}, {65, 33}, {131, 47}, {200, 3}};
  const struct {
    int r;
    float eps;
  } cases[] = {{1, 0.3F}, {3, 0.0025F}, {6, 0.0025F}, {9, 0.01F}};
  for (const auto& sz : sizes)
    for (const auto& cs : cases) {
      const int w = sz[0], h = sz[1];
      ImageRGBF guide(w, h);
      ImageF p(w, h);
      Image<float, 4> packed(w, h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          for (int c = 0; c < 3; ++c)
            guide.at(x, y, c) = packed.at(x, y, c) =
                ((x / 4 + y / 3 + c) % 3) * 0.3F + 0.1F * u(rng);
          p.at(x, y) = packed.at(x, y, 3) = u(rng) < 0.5F ? 0.0F : 1.0F;
        }
      GuidedFilter gf(context(), cs.r, cs.eps, GuidedFilter::Output::Raw);
      DeviceImageF4 in(context(), packed), ab;
      DeviceImageF out;
      gf.coefficients(in, ab);
      gf.apply(ab, nullptr, &in, nullptr, &out);
      const auto got = download(out);
      const auto want = guided_filter_reference(guide, p, {cs.r, cs.eps, 1});
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          ASSERT_NEAR(got.at(x, y), want.at(x, y), 2e-4)
              << w << "x" << h << " r=" << cs.r << " at " << x << "," << y;
    }
}

// The row-streaming filter (cvf_guided.cl) on packed input against the reference: odd widths
// (partial vectors of 16), heights that make several strips, radii up to the maximum.
TEST(StripGuidedFilterDevice, MatchesReferenceOnRandomSizes) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  const int sizes[][2] = {{1, 1}, {7, 5}, {17, 3}, {63, 17}, {65, 33}, {131, 47}, {37, 260}};
  const struct {
    int r;
    float eps;
  } cases[] = {{0, 0.01F}, {1, 0.3F}, {3, 0.0025F}, {6, 0.0025F}, {16, 0.01F}};
  for (const auto& cs : cases) {
    StripGuidedFilter gf(context(), cs.r, cs.eps, StripGuidedFilter::Input::Packed,
                         StripGuidedFilter::Output::Raw);
    for (const auto& sz : sizes) {
      const int w = sz[0], h = sz[1];
      ImageRGBF guide(w, h);
      ImageF p(w, h);
      Image<float, 4> packed(w, h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          for (int c = 0; c < 3; ++c)
            guide.at(x, y, c) = packed.at(x, y, c) =
                ((x / 4 + y / 3 + c) % 3) * 0.3F + 0.1F * u(rng);
          p.at(x, y) = packed.at(x, y, 3) = u(rng) < 0.5F ? 0.0F : 1.0F;
        }
      DeviceImageF4 in(context(), packed);
      DeviceImageF out(context(), w, h);
      set_args_from(gf.kernel(), StripGuidedFilter::kFirstArg, in.buffer(), out.buffer());
      gf.run(w, h);
      const auto got = download(out);
      const auto want = guided_filter_reference(guide, p, {cs.r, cs.eps, 1});
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          ASSERT_NEAR(got.at(x, y), want.at(x, y), 2e-4)
              << w << "x" << h << " r=" << cs.r << " at " << x << "," << y;
    }
  }
}

TEST(StripGuidedFilterDevice, RejectsRadiiBeyondThePadding) {
  EXPECT_THROW(StripGuidedFilter(context(), StripGuidedFilter::kMaxRadius + 1, 0.01F,
                                 StripGuidedFilter::Input::Packed, StripGuidedFilter::Output::Raw),
               std::invalid_argument);
}

void expect_cvf_matches_in(CvfLayout layout, int w, int h, std::uint32_t seed,
                           const CvfParams& params) {
  SCOPED_TRACE(testing::Message() << w << "x" << h << " seed " << seed << " subsample "
                                  << params.wide.subsample << " layout " << int(layout));
  const auto s = random_scene(w, h, seed);
  const auto ref = cvf_reference(s.colour, s.depth, s.virt, params);
  CvfMatte cvf(context(), params, /*trace=*/true, layout);
  ASSERT_EQ(cvf.layout(), layout);
  DeviceImageRGB8 colour(context(), s.colour);
  DeviceDepthImage depth(context(), s.depth);
  DeviceImageF virt(context(), s.virt), alpha;
  cvf.process({&colour, &depth, &virt}, alpha);
  const auto got = download(alpha);
  const auto t = cvf.download_trace();

  EXPECT_EQ(t.categories, ref.categories);
  for (std::size_t i = 0; i < t.band.elements().size(); ++i)
    ASSERT_EQ(t.band.elements()[i] != 0, ref.band.elements()[i] != 0) << i;
  EXPECT_EQ(t.models.infront, ref.models.infront);
  EXPECT_EQ(t.models.behind, ref.models.behind);
  if (params.wide.subsample == 1) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) ASSERT_NEAR(t.wide_input.at(x, y, 3), ref.cost.at(x, y), 1e-6);
  }

  // The threshold may flip where the wide filter's output is within float noise of 0.5.
  int flips = 0, undecided = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (std::fabs(ref.wide.at(x, y) - 0.5F) < 1e-3F) ++undecided;
      if (t.feather_input.at(x, y, 3) != ref.mask.at(x, y)) {
        ++flips;
        EXPECT_LT(std::fabs(ref.wide.at(x, y) - 0.5F), 1e-3F) << x << "," << y;
      }
    }
  EXPECT_LE(flips, undecided);
  // Alpha agrees wherever no mask pixel in the feather window flipped.
  int far = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (std::fabs(got.at(x, y) - ref.alpha.at(x, y)) > 1e-3F) ++far;
  EXPECT_LE(far, 25 * flips) << "alpha differs on " << far << " pixels";
}

// Both device layouts (row-streaming strips for CPUs, tiles for GPUs) on PoCL.
void expect_cvf_matches(int w, int h, std::uint32_t seed, const CvfParams& params) {
  expect_cvf_matches_in(CvfLayout::Strips, w, h, seed, params);
  expect_cvf_matches_in(CvfLayout::Tiles, w, h, seed, params);
}

TEST(CvfDevice, AutoLayoutIsStripsOnCpuDevices) {
  CvfMatte cvf(context(), CvfParams{});
  EXPECT_EQ(cvf.layout(), context().info().type == "CPU" ? CvfLayout::Strips : CvfLayout::Tiles);
}

TEST(CvfDevice, MatchesReferenceExactFilter) {
  CvfParams p;
  p.wide.subsample = 1;
  expect_cvf_matches(97, 61, 1, p);
  expect_cvf_matches(64, 48, 2, p);
  expect_cvf_matches(131, 9, 3, p);
}

TEST(CvfDevice, MatchesReferenceFastFilter) {
  CvfParams p;
  p.wide.subsample = 2;
  expect_cvf_matches(97, 61, 4, p);
  expect_cvf_matches(160, 121, 5, p);
  p.bins_per_channel = 8;
  expect_cvf_matches(75, 40, 6, p);
}

// Tall frames run in several strips (each warms up on the rows above it); erosion and band
// radii from 0 to the maximum of the row-streaming kernels.
TEST(CvfDevice, MatchesReferenceAcrossStripsAndRadii) {
  CvfParams p;
  expect_cvf_matches(70, 250, 8, p);
  p.wide.subsample = 1;
  expect_cvf_matches(45, 199, 9, p);
  p.wide.subsample = 2;
  p.categorise.erosion_px = 0;
  p.band_px = 0;
  expect_cvf_matches(81, 130, 10, p);
  p.categorise.erosion_px = 16;
  p.band_px = 16;
  expect_cvf_matches(96, 140, 11, p);
}

TEST(CvfDevice, FallsBackToTheDepthTestWithFewSamples) {
  CvfParams p;
  p.min_samples = 1000000;
  expect_cvf_matches(50, 30, 7, p);
}

}  // namespace
}  // namespace probeless::occlusion
