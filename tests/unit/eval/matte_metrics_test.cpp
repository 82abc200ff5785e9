// The evaluator's metrics on hand-made mattes with known answers.
#include "lab/eval/matte_metrics.hpp"

#include <gtest/gtest.h>

namespace probeless::eval {
namespace {

TEST(MatteMetrics, MseAndSadOverTheMaskOnly) {
  ImageF truth(4, 1), alpha(4, 1);
  ImageGray8 mask(4, 1, 255);
  truth.at(0, 0) = 1.0F;  // errors: 1, 0.5, 0, (masked out) 1
  alpha.at(1, 0) = 0.5F;
  alpha.at(3, 0) = 1.0F;
  mask.at(3, 0) = 0;
  EXPECT_DOUBLE_EQ(*matte_mse(alpha, truth, mask), (1.0 + 0.25 + 0.0) / 3.0);
  EXPECT_DOUBLE_EQ(matte_sad(alpha, truth, mask), 1.5 / 1000.0);
  EXPECT_FALSE(matte_mse(alpha, truth, ImageGray8(4, 1)).has_value());
}

TEST(MatteMetrics, SilhouetteBandIsTheNeighbourhoodOfTrueEdges) {
  // Truth: visible on the left half of a 30 x 5 object, hidden on the right.
  ImageF truth(30, 5);
  ImageGray8 mask(30, 5, 255);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 15; ++x) truth.at(x, y) = 1.0F;
  const auto band = silhouette_band(truth, mask, 3);
  for (int x = 0; x < 30; ++x)
    EXPECT_EQ(band.at(x, 2) != 0, x >= 11 && x <= 18) << x;  // edges at x = 14 and 15
  // The object's own outline (mask edge) is no silhouette.
  ImageF flat(10, 10, 1.0F);
  ImageGray8 m2(10, 10);
  for (int y = 2; y < 8; ++y)
    for (int x = 2; x < 8; ++x) m2.at(x, y) = 255;
  const auto none = silhouette_band(flat, m2, 2);
  for (auto v : none.elements()) EXPECT_EQ(v, 0);
}

TEST(MatteMetrics, TemporalNoiseIsThePerPixelVariance) {
  // Pixel 0 alternates 0 / 1 (variance 0.25), pixel 1 is constant, pixel 2 is masked out in
  // one frame and so left out.
  std::vector<ImageF> alphas, truths;
  std::vector<ImageGray8> masks;
  for (int k = 0; k < 4; ++k) {
    ImageF a(3, 1);
    a.at(0, 0) = k % 2 ? 1.0F : 0.0F;
    a.at(1, 0) = 0.3F;
    a.at(2, 0) = k % 2 ? 1.0F : 0.0F;
    ImageGray8 m(3, 1, 255);
    if (k == 2) m.at(2, 0) = 0;
    alphas.push_back(a);
    truths.emplace_back(3, 1);
    masks.push_back(m);
  }
  EXPECT_DOUBLE_EQ(*temporal_noise(alphas, truths, masks), 0.25 / 2.0);
  alphas.resize(1);
  truths.resize(1);
  masks.resize(1);
  EXPECT_FALSE(temporal_noise(alphas, truths, masks).has_value());
}

}  // namespace
}  // namespace probeless::eval
