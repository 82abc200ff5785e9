// The sim protocol's parsing and metrics (lab/eval/sim_dataset.hpp, sim_metrics.hpp) on
// hand-made inputs with known answers.
#include "lab/eval/sim_metrics.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "lab/eval/matte_metrics.hpp"
#include "lab/eval/sim_dataset.hpp"
#include "support/cl_context.hpp"

namespace probeless::eval {
namespace {

TEST(SimProtocol, DefaultsAndOverrides) {
  const SimProtocolOptions d = parse_sim_protocol("");
  EXPECT_EQ(d.sim.trajectory, sim::TrajectoryKind::Tabletop);
  EXPECT_TRUE(d.sim.near_occluder);
  EXPECT_EQ(d.sim.start_s, 1.5);
  EXPECT_EQ(d.frames, 90);
  EXPECT_EQ(d.sim.max_frames, 90);
  EXPECT_FALSE(d.sim.realtime) << "every frame, in order";
  const SimProtocolOptions o = parse_sim_protocol("frames=16,near_occluder=0,seed=4,realtime=1");
  EXPECT_EQ(o.frames, 16);
  EXPECT_FALSE(o.sim.near_occluder);
  EXPECT_EQ(o.sim.seed, 4u);
  EXPECT_FALSE(o.sim.realtime);
  EXPECT_EQ(d.lift_m, 0.0);
  // The protocol's own key, taken out before the sim's parser sees it, wherever it stands.
  const SimProtocolOptions lifted = parse_sim_protocol("trajectory=orbit,lift=0.25,seed=3");
  EXPECT_DOUBLE_EQ(lifted.lift_m, 0.25);
  EXPECT_EQ(lifted.sim.trajectory, sim::TrajectoryKind::Orbit);
  EXPECT_EQ(lifted.sim.seed, 3u);
}

TEST(SimProtocol, BadOptionsAreClearErrors) {
  for (const char* spec :
       {"frames=1", "frames=100000", "trajectory=calibration", "bogus=1",
        "near_occluder=yes please", "lift=-0.1", "lift=3", "lift=", "lift=0.2m"}) {
    EXPECT_THROW(parse_sim_protocol(spec), std::invalid_argument) << spec;
  }
  try {
    parse_sim_protocol("bogus=1");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'bogus'"), std::string::npos) << e.what();
  }
}

TEST(SimMetrics, DilateMaskIsAChebyshevNeighbourhood) {
  ImageGray8 seeds(9, 7);
  seeds.at(4, 3) = 1;
  const ImageGray8 d = dilate_mask(seeds, 2);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 9; ++x)
      EXPECT_EQ(d.at(x, y) != 0, std::abs(x - 4) <= 2 && std::abs(y - 3) <= 2) << x << "," << y;
  const ImageGray8 none = dilate_mask(ImageGray8(5, 5), 3);
  for (auto v : none.elements()) EXPECT_EQ(v, 0);
}

TEST(SimMetrics, WindowedTemporalNoiseSkipsPixelsWhoseTruthChanges) {
  // Pixel 0: truth constant, alpha alternating 0 / 1 (variance 0.25). Pixel 1: the truth
  // flips in the second window only; alpha follows it exactly but its error alternates.
  std::vector<ImageF> alphas, truths;
  std::vector<ImageGray8> masks;
  for (int k = 0; k < 8; ++k) {
    ImageF a(2, 1), t(2, 1);
    a.at(0, 0) = k % 2 ? 1.0F : 0.0F;
    t.at(1, 0) = k >= 6 ? 1.0F : 0.0F;
    a.at(1, 0) = k % 2 ? 0.5F : 0.0F;
    alphas.push_back(a);
    truths.push_back(t);
    masks.emplace_back(2, 1, 255);
  }
  // Whole sequence (window 0): the static definition over both pixels.
  EXPECT_EQ(windowed_temporal_noise(alphas, truths, masks, 0),
            temporal_noise(alphas, truths, masks));
  // Windows of 4: the first counts both pixels (0.25 and 0.0625), the second only pixel 0.
  const double first = (0.25 + 0.0625) / 2, second = 0.25;
  EXPECT_DOUBLE_EQ(*windowed_temporal_noise(alphas, truths, masks, 4), (first + second) / 2);
}

TEST(SimMetrics, CompositeErrorAtFractionalPixelsOnly) {
  EvalFrame f;
  f.colour = ImageRGB8(3, 1, 100);
  f.virtual_colour = ImageRGBA8(3, 1, 200);
  f.truth = ImageF(3, 1, 1.0F);
  f.mask = ImageGray8(3, 1, 255);
  ImageF alpha(3, 1);
  alpha.at(0, 0) = 0.5F;  // fractional: composite 150 against the truth's 200
  alpha.at(1, 0) = 1.0F;  // not fractional: not scored
  alpha.at(2, 0) = 0.0F;
  ImageRGB8 composite(3, 1, 150);
  const double want = (50.0 / 255) * (50.0 / 255);
  EXPECT_DOUBLE_EQ(*fractional_composite_error(f, alpha, composite), want);
  // The true foreground colour replaces the observed one where the truth is hidden.
  f.truth.at(0, 0) = 0.0F;
  f.true_foreground = ImageRGB8(3, 1, 150);
  EXPECT_DOUBLE_EQ(*fractional_composite_error(f, alpha, composite), 0.0);
  EXPECT_FALSE(fractional_composite_error(f, ImageF(3, 1), composite).has_value());
  EXPECT_THROW(fractional_composite_error(f, ImageF(2, 1), composite), std::invalid_argument);
}

TEST(SimProtocol, MixedPixelsSplitByTheObjectGetFractionalTruthAndTheirForeground) {
  EXPECT_EQ(parse_sim_protocol("").sim.edge_samples, 4) << "silhouettes are mixed pixels";
  EvalFrame f;
  f.colour = ImageRGB8(4, 1, 100);
  f.virtual_depth_mm = ImageF(4, 1, 1000.0F);
  f.truth = ImageF(4, 1, 1.0F);
  f.mask = ImageGray8(4, 1, 255);
  f.mask.at(3, 0) = 0;  // not on the object
  const std::vector<MixedPixel> mixed = {
      {0, 0.25F, 500, 2000, {10, 20, 30}, {200, 200, 200}},  // hand over the wall: split
      {1, 0.5F, 600, 900, {40, 50, 60}, {70, 80, 90}},       // both in front: truth stays
      {2, 0.5F, 1200, 1500, {40, 50, 60}, {70, 80, 90}},     // both behind
      {3, 0.5F, 500, 2000, {40, 50, 60}, {70, 80, 90}},      // off the object
      {9, 0.5F, 500, 2000, {40, 50, 60}, {70, 80, 90}},      // outside the frame: ignored
  };
  apply_mixed_pixels(mixed, f);
  EXPECT_FLOAT_EQ(f.truth.at(0, 0), 0.75F) << "the wall's share of the pixel";
  EXPECT_EQ(f.true_foreground.at(0, 0, 0), 10);
  EXPECT_EQ(f.true_foreground.at(0, 0, 2), 30);
  for (int x = 1; x < 4; ++x) {
    EXPECT_EQ(f.truth.at(x, 0), 1.0F) << x;
    EXPECT_EQ(f.true_foreground.at(x, 0, 0), 100) << "the observed colour at " << x;
  }
  EvalFrame none;
  apply_mixed_pixels({}, none);
  EXPECT_TRUE(none.true_foreground.empty());
}

TEST(SimComposite, TheForegroundEstimateLowersTheErrorOnAMixedEdge) {
  // A skin-coloured hand (left) over a blue-grey wall (right), a vertical silhouette through a
  // column of mixed pixels (the hand covers 60 % of each, mixed in linear light as the sim's
  // edge samples do), the blue object behind both and the matte exactly the truth.
  const int w = 48, h = 32, edge = 24;
  const std::array<std::uint8_t, 3> hand{200, 140, 110}, wall{60, 90, 140};
  const auto lin = [](std::uint8_t v) { return std::pow(v / 255.0, 2.2); };
  EvalFrame f;
  f.colour = ImageRGB8(w, h);
  f.true_foreground = ImageRGB8(w, h);
  f.virtual_colour = ImageRGBA8(w, h, 255);
  f.virtual_depth_mm = ImageF(w, h, 1000.0F);
  f.truth = ImageF(w, h);
  f.mask = ImageGray8(w, h, 255);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        const auto k = static_cast<std::size_t>(c);
        const double mix = 0.6 * lin(hand[k]) + 0.4 * lin(wall[k]);
        f.colour.at(x, y, c) =
            x < edge   ? hand[k]
            : x > edge ? wall[k]
                       : static_cast<std::uint8_t>(std::lround(255 * std::pow(mix, 1 / 2.2)));
        f.true_foreground.at(x, y, c) = x <= edge ? hand[k] : f.colour.at(x, y, c);
        f.virtual_colour.at(x, y, c) = c == 2 ? 230 : 20;
      }
      f.truth.at(x, y) = x < edge ? 0.0F : x > edge ? 1.0F : 0.4F;
    }
  auto& ctx = testing::cl_context();
  const DeviceImageRGB8 colour(ctx, f.colour);
  const DeviceImageF virt(ctx, f.virtual_depth_mm), alpha(ctx, f.truth);
  SimComposite composite(ctx);
  const CompositeErrors e = composite.error(f, colour, virt, alpha, f.truth);
  ASSERT_GT(e.observed, 0.0) << "the observed mix carries the wall into the object";
  EXPECT_LT(e.estimated, 0.1 * e.observed);
  EXPECT_GE(e.estimated, 0.0);
  // Nothing fractional, or no virtual colour (not the sim protocol): nothing to score.
  const ImageF all_visible(w, h, 1.0F);
  const DeviceImageF hard(ctx, all_visible);
  const CompositeErrors none = composite.error(f, colour, virt, hard, all_visible);
  EXPECT_EQ(none.estimated, -1);
  EXPECT_EQ(none.observed, -1);
  f.virtual_colour = {};
  EXPECT_EQ(composite.error(f, colour, virt, alpha, f.truth).observed, -1);
}

}  // namespace
}  // namespace probeless::eval
