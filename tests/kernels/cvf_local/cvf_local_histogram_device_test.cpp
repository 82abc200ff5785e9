// The device stage of CVF with local colour models against its CPU reference
// (local_costs_reference): costs and softness on random scenes, the test sizes of every kernel
// (odd widths, partial tiles and work-groups), several tile sizes, bins and prior radii, and
// the depth-test fallback without colour models.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>

#include "kernels/occlusion/common/categorise_reference.hpp"
#include "kernels/occlusion/cvf/cvf_local_histogram.hpp"
#include "support/cl_context.hpp"

namespace probeless::occlusion {
namespace {

struct Frame {
  ImageRGB8 colour;
  DepthImage depth;
  ImageF virt;
};

// Depth in 5x5 blocks (near, far, unknown, tie; a margin off the object), colours from a small
// palette with noise whose choice depends on the block's class, so tiles differ.
Frame random_frame(int w, int h, std::mt19937& rng, bool only_infront = false) {
  Frame f{ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h)};
  std::uniform_int_distribution<int> cls(0, 9), noise(-12, 12), pal(0, 3);
  const std::uint8_t palette[4][3] = {{200, 30, 30}, {30, 200, 30}, {30, 30, 200}, {200, 200, 60}};
  std::vector<int> block(static_cast<std::size_t>((w / 5 + 1) * (h / 5 + 1)));
  for (auto& b : block) b = cls(rng);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int b = block[static_cast<std::size_t>((y / 5) * (w / 5 + 1) + x / 5)];
      f.virt.at(x, y) = (x + y) % 23 == 0 ? 0.0F : 1000.0F;  // a few off-object pixels
      const std::uint16_t d = only_infront ? (b < 3 ? 0 : 500)
                              : b < 4      ? 500
                              : b < 8      ? 2000
                              : b < 9      ? 0
                                           : 1005;
      f.depth.at(x, y) = d;
      const int p = (b + (x < w / 2 ? 0 : 1) + pal(rng) / 3) % 4;
      for (int k = 0; k < 3; ++k)
        f.colour.at(x, y, k) =
            static_cast<std::uint8_t>(std::clamp(palette[p][k] + noise(rng), 0, 255));
    }
  return f;
}

// Returns whether the scene had colour models (so the tests can insist on both paths).
bool expect_matches_reference(const Frame& f, const CvfLocalParams& params, const char* what) {
  auto& ctx = testing::cl_context();
  const auto cats = categorise_reference(f.depth, f.virt, params.cvf.categorise);
  const auto band = process_band_reference(cats, params.cvf.band_px);
  const auto ref = local_costs_reference(f.colour, cats, band, f.depth, f.virt, params);

  DeviceImageRGB8 colour(ctx, f.colour);
  DeviceDepthImage depth(ctx, f.depth);
  DeviceImageF virt(ctx, f.virt);
  DeviceImageGray8 dcats(ctx, cats), dband(ctx, band);
  CvfLocalHistogram stage(ctx, params);
  stage.run({&colour, &depth, &virt}, dcats, dband);
  const auto cost = stage.cost().download(ctx.queue());
  const auto soft = stage.softness().download(ctx.queue());
  EXPECT_EQ(stage.colour_models_valid(), ref.colour_models_valid) << what;
  int bad = 0;
  for (int y = 0; y < f.colour.height(); ++y)
    for (int x = 0; x < f.colour.width(); ++x) {
      if (std::fabs(cost.at(x, y) - ref.cost.at(x, y)) > 1e-4F ||
          std::fabs(soft.at(x, y) - ref.softness.at(x, y)) > 1e-4F) {
        if (++bad <= 5) {
          ADD_FAILURE() << what << " at " << x << "," << y << ": cost " << cost.at(x, y) << " vs "
                        << ref.cost.at(x, y) << ", softness " << soft.at(x, y) << " vs "
                        << ref.softness.at(x, y);
        }
      }
    }
  EXPECT_EQ(bad, 0) << what;
  return ref.colour_models_valid;
}

TEST(CvfLocalHistogramDevice, MatchesReferenceOnRandomScenes) {
  std::mt19937 rng(11);
  int run = 0, with_models = 0;
  for (const auto& [w, h] : testing::kernel_test_sizes()) {
    CvfLocalParams p;
    p.cvf.min_samples = 5;  // the tiny sizes too have colour models sometimes
    // Cycle through the variants rather than multiplying the VGA cases.
    p.tile_px = std::array{32, 7, 16}[run % 3];
    p.prior_radius = std::array{3, 0, 2}[run % 3];
    p.cvf.bins_per_channel = run % 2 ? 8 : 4;
    p.soft_where_ambiguous = run % 4 != 1;
    const auto f = random_frame(w, h, rng);
    with_models += expect_matches_reference(
        f, p,
        (std::to_string(w) + "x" + std::to_string(h) + " tile " + std::to_string(p.tile_px))
            .c_str());
    ++run;
  }
  std::uniform_int_distribution<int> size(1, 150);
  for (int k = 0; k < 6; ++k) {
    CvfLocalParams p;
    p.tile_px = 1 + k * 9;
    p.cvf.categorise.erosion_px = k % 3;
    const int w = size(rng) | 1, h = size(rng);
    with_models +=
        expect_matches_reference(random_frame(w, h, rng), p,
                                 ("random " + std::to_string(w) + "x" + std::to_string(h)).c_str());
  }
  EXPECT_GE(with_models, 8) << "most scenes must exercise the colour models, not the fallback";
}

TEST(CvfLocalHistogramDevice, FallsBackToTheDepthTestWithoutColourModels) {
  std::mt19937 rng(5);
  const auto f = random_frame(97, 61, rng, /*only_infront=*/true);
  EXPECT_FALSE(expect_matches_reference(f, CvfLocalParams{}, "no behind pixels"));
}

TEST(CvfLocalHistogramDevice, RejectsWhatTheDeviceCannotHold) {
  auto& ctx = testing::cl_context();
  CvfLocalParams p;
  p.tile_px = 0;
  EXPECT_THROW(CvfLocalHistogram(ctx, p), std::invalid_argument);
  p.tile_px = 32;
  p.cvf.bins_per_channel = 16;
  EXPECT_THROW(CvfLocalHistogram(ctx, p), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::occlusion

namespace probeless::occlusion {
namespace {

// Not a test (no threshold; it cannot fail): the stage's device time at 640x480, for
// docs/occlusion.md. Run with --gtest_also_run_disabled_tests --gtest_filter='*Timing*'.
TEST(CvfLocalHistogramDevice, DISABLED_TimingVga) {
  auto& ctx = testing::cl_context();
  std::mt19937 rng(1);
  const auto f = random_frame(640, 480, rng);
  for (const int prior : {3, 0}) {
    CvfLocalParams p;
    p.prior_radius = prior;
    const auto cats = categorise_reference(f.depth, f.virt, p.cvf.categorise);
    const auto band = process_band_reference(cats, p.cvf.band_px);
    DeviceImageRGB8 colour(ctx, f.colour);
    DeviceDepthImage depth(ctx, f.depth);
    DeviceImageF virt(ctx, f.virt);
    DeviceImageGray8 dcats(ctx, cats), dband(ctx, band);
    CvfLocalHistogram stage(ctx, p);
    std::vector<double> ms;
    for (int k = 0; k < 60; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      stage.run({&colour, &depth, &virt}, dcats, dband);
      ctx.queue().finish();
      ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin() + 10, ms.end());
    std::printf(
        "cvf_local_histogram 640x480, prior radius %d: p50 %.2f ms, min %.2f ms (50 frames "
        "after 10)\n",
        prior, ms[10 + 25], ms[10]);
  }
}

}  // namespace
}  // namespace probeless::occlusion
