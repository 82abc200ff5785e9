// The sim protocol's parsing and metrics (lab/eval/sim_dataset.hpp, sim_metrics.hpp) on
// hand-made inputs with known answers.
#include "lab/eval/sim_metrics.hpp"

#include <gtest/gtest.h>

#include "lab/eval/matte_metrics.hpp"
#include "lab/eval/sim_dataset.hpp"

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
}

TEST(SimProtocol, BadOptionsAreClearErrors) {
  for (const char* spec : {"frames=1", "frames=100000", "trajectory=calibration", "bogus=1",
                           "near_occluder=yes please"}) {
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

}  // namespace
}  // namespace probeless::eval
