#include "lab/eval/light_eval.hpp"

#include <gtest/gtest.h>

namespace probeless::light {
namespace {

envmap::ImageRGBAF constant(int m, float v, float alpha) {
  envmap::ImageRGBAF t = envmap::make_texels(m);
  for (int y = 0; y < 6 * m; ++y)
    for (int x = 0; x < m; ++x) {
      for (int c = 0; c < 3; ++c) t.at(x, y, c) = v;
      t.at(x, y, 3) = alpha;
    }
  return t;
}

TEST(LightEval, AverageObservedNeedsEveryTexelOfTheBlock) {
  envmap::ImageRGBAF t = constant(4, 1, 1);
  t.at(0, 0, 0) = 5;          // block (0,0) of face 0 averages to 2
  t.at(3, 4 * 4 + 3, 3) = 0;  // one unobserved texel in face 4's block (1,1)
  std::vector<bool> observed;
  const envmap::ImageRGBAF a = average_observed(t, 2, observed);
  EXPECT_FLOAT_EQ(a.at(0, 0, 0), 2.0F);
  EXPECT_TRUE(observed[0]);
  EXPECT_FALSE(observed[(4 * 2 + 1) * 2 + 1]);
  EXPECT_TRUE(observed[(4 * 2 + 1) * 2 + 0]);
  EXPECT_THROW(average_observed(t, 3, observed), std::invalid_argument);
}

TEST(LightEval, RelativeRmsePerFaceOverObservedTexels) {
  const int m = 2;
  const envmap::ImageRGBAF truth = constant(m, 10, 1);
  envmap::ImageRGBAF est = constant(m, 10, 1);
  std::vector<bool> observed(6 * m * m, true);
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < m; ++x) {
      for (int c = 0; c < 3; ++c) est.at(x, 1 * m + y, c) = 11;         // face -x: 10 % high
      observed[static_cast<std::size_t>((5 * m + y) * m + x)] = false;  // -z unobserved
    }
  est.at(0, 5 * m, 0) = 1000;  // unobserved: ignored
  const TruthComparison c = compare_cubemaps(est, truth, observed);
  ASSERT_TRUE(c.faces[0].relative_rmse.has_value());
  EXPECT_DOUBLE_EQ(*c.faces[0].relative_rmse, 0.0);
  EXPECT_NEAR(*c.faces[1].relative_rmse, 0.1, 1e-12);
  EXPECT_FALSE(c.faces[5].relative_rmse.has_value());
  EXPECT_EQ(c.faces[5].observed, 0);
  EXPECT_EQ(c.all.observed, 5 * m * m);
  EXPECT_NEAR(*c.all.relative_rmse, std::sqrt(0.01 / 5), 1e-12);
}

}  // namespace
}  // namespace probeless::light
