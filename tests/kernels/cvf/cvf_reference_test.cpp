// The CPU references of CVF against first principles: the guided filter against brute-force
// window sums in double precision, the categories, band, histograms and costs on hand-made
// inputs with known answers, and the whole method on a scene where colour decides.
#include "kernels/occlusion/cvf/cvf_reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/occlusion/common/categorise_reference.hpp"
#include "kernels/occlusion/common/guided_filter_reference.hpp"

namespace probeless::occlusion {
namespace {

// He et al.'s guided filter straight from its definition: every window sum by a loop.
ImageF brute_force_guided(const ImageRGBF& I, const ImageF& p, int r, double eps) {
  const int w = I.width(), h = I.height();
  std::vector<double> a(static_cast<std::size_t>(w) * h * 4);
  auto window = [&](int x, int y, auto&& fn) {
    for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
      for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i) fn(i, j);
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double n = 0, mi[3] = {0, 0, 0}, mp = 0, mip[3] = {0, 0, 0}, mii[3][3] = {};
      window(x, y, [&](int i, int j) {
        n += 1;
        mp += p.at(i, j);
        for (int c = 0; c < 3; ++c) {
          mi[c] += I.at(i, j, c);
          mip[c] += double(I.at(i, j, c)) * p.at(i, j);
          for (int d = 0; d < 3; ++d) mii[c][d] += double(I.at(i, j, c)) * I.at(i, j, d);
        }
      });
      mp /= n;
      double S[3][3], cov[3];
      for (int c = 0; c < 3; ++c) {
        mi[c] /= n;
      }
      for (int c = 0; c < 3; ++c) {
        cov[c] = mip[c] / n - mi[c] * mp;
        for (int d = 0; d < 3; ++d) S[c][d] = mii[c][d] / n - mi[c] * mi[d] + (c == d ? eps : 0);
      }
      // Cramer's rule.
      auto det3 = [](double m[3][3]) {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
      };
      const double D = det3(S);
      double coef[3];
      for (int k = 0; k < 3; ++k) {
        double M[3][3];
        for (int c = 0; c < 3; ++c)
          for (int d = 0; d < 3; ++d) M[c][d] = d == k ? cov[c] : S[c][d];
        coef[k] = det3(M) / D;
      }
      const std::size_t o = (static_cast<std::size_t>(y) * w + x) * 4;
      for (int k = 0; k < 3; ++k) a[o + k] = coef[k];
      a[o + 3] = mp - coef[0] * mi[0] - coef[1] * mi[1] - coef[2] * mi[2];
    }
  ImageF q(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double m[4] = {0, 0, 0, 0}, n = 0;
      window(x, y, [&](int i, int j) {
        n += 1;
        for (int k = 0; k < 4; ++k) m[k] += a[(static_cast<std::size_t>(j) * w + i) * 4 + k];
      });
      q.at(x, y) = static_cast<float>(
          (m[0] * I.at(x, y, 0) + m[1] * I.at(x, y, 1) + m[2] * I.at(x, y, 2) + m[3]) / n);
    }
  return q;
}

ImageRGBF random_guide(int w, int h, std::mt19937& rng) {
  ImageRGBF g(w, h);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  // Piecewise-constant regions plus noise, so windows see both edges and flat areas.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) g.at(x, y, c) = ((x / 5 + y / 7 + c) % 3) * 0.3F + 0.1F * u(rng);
  return g;
}

TEST(GuidedFilterReference, MatchesBruteForceOnRandomSizes) {
  std::mt19937 rng(7);
  const int sizes[][2] = {{1, 1}, {5, 3}, {17, 9}, {33, 20}, {8, 41}};
  const int radii[] = {1, 2, 6};
  const double eps[] = {0.0025, 0.3, 1e-4};
  for (const auto& s : sizes)
    for (int r : radii)
      for (double e : eps) {
        const auto I = random_guide(s[0], s[1], rng);
        ImageF p(s[0], s[1]);
        std::uniform_real_distribution<float> u(0.0F, 1.0F);
        for (auto& v : p.elements()) v = u(rng);
        const auto got = guided_filter_reference(I, p, {r, float(e), 1});
        const auto want = brute_force_guided(I, p, r, e);
        for (int y = 0; y < s[1]; ++y)
          for (int x = 0; x < s[0]; ++x)
            ASSERT_NEAR(got.at(x, y), want.at(x, y), 2e-5)
                << s[0] << "x" << s[1] << " r=" << r << " eps=" << e << " at " << x << "," << y;
      }
}

TEST(GuidedFilterReference, ConstantInputStaysConstantAtAnySubsample) {
  std::mt19937 rng(3);
  const auto I = random_guide(37, 23, rng);
  ImageF p(37, 23, 0.25F);
  for (int s : {1, 2, 3}) {
    const auto q = guided_filter_reference(I, p, {6, 0.0025F, s});
    for (float v : q.elements()) ASSERT_NEAR(v, 0.25F, 1e-5) << "subsample " << s;
  }
}

TEST(GuidedFilterReference, FastFilterKeepsAnEdgeThatFollowsTheGuide) {
  // Input = guide's red channel: the exact filter with small eps reproduces it nearly, and the
  // subsampled filter stays close away from the single edge.
  ImageRGBF I(40, 30);
  ImageF p(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const float v = x < 17 ? 0.2F : 0.8F;
      for (int c = 0; c < 3; ++c) I.at(x, y, c) = v;
      p.at(x, y) = v;
    }
  const auto exact = guided_filter_reference(I, p, {6, 1e-4F, 1});
  const auto fast = guided_filter_reference(I, p, {6, 1e-4F, 2});
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      EXPECT_NEAR(exact.at(x, y), p.at(x, y), 0.01);
      EXPECT_NEAR(fast.at(x, y), p.at(x, y), 0.02);
    }
}

TEST(Categorise, DepthTestWithToleranceAndUnknown) {
  EXPECT_EQ(raw_category(1000, 0.0F, 15), Category::Ignore);
  EXPECT_EQ(raw_category(0, 1000.0F, 15), Category::Process);
  EXPECT_EQ(raw_category(985, 1000.0F, 15), Category::Process);
  EXPECT_EQ(raw_category(1015, 1000.0F, 15), Category::Process);
  EXPECT_EQ(raw_category(984, 1000.0F, 15), Category::Infront);
  EXPECT_EQ(raw_category(1016, 1000.0F, 15), Category::Behind);
}

TEST(Categorise, ErodesInfrontAndBehindBordersByExactlyThePixelCount) {
  // Left half real at 500 mm (infront), right half at 2000 mm (behind); object everywhere
  // except the last two rows.
  const int w = 20, h = 8;
  DepthImage real(w, h);
  ImageF virt(w, h, 1000.0F);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) real.at(x, y) = x < 10 ? 500 : 2000;
  for (int x = 0; x < w; ++x) virt.at(x, h - 1) = virt.at(x, h - 2) = 0.0F;
  const auto cats = categorise_reference(real, virt, {15.0F, 3});
  for (int x = 0; x < w; ++x) {
    const auto want = x < 7 ? Category::Infront : x < 13 ? Category::Process : Category::Behind;
    EXPECT_EQ(static_cast<Category>(cats.at(x, 0)), want) << x;
    // Off-object rows are ignored, and do not erode the rows next to them.
    EXPECT_EQ(static_cast<Category>(cats.at(x, h - 1)), Category::Ignore);
    EXPECT_EQ(static_cast<Category>(cats.at(x, h - 3)), want) << x;
  }
  // A hole (unknown depth) erodes nothing: only the other known class does.
  DepthImage flat(w, 12, 500);
  flat.at(10, 6) = 0;
  const auto c2 = categorise_reference(flat, ImageF(w, 12, 1000.0F), {15.0F, 3});
  int process = 0;
  for (auto v : c2.elements()) process += v == std::uint8_t(Category::Process);
  EXPECT_EQ(process, 1);
  // A behind pixel inside an infront region erodes a 7x7 square around it.
  flat.at(10, 6) = 2000;
  const auto c3 = categorise_reference(flat, ImageF(w, 12, 1000.0F), {15.0F, 3});
  process = 0;
  for (auto v : c3.elements()) process += v == std::uint8_t(Category::Process);
  EXPECT_EQ(process, 49);
}

TEST(Categorise, BandMarksTheProcessNeighbourhood) {
  CategoryImage cats(30, 5, std::uint8_t(Category::Behind));
  cats.at(12, 2) = std::uint8_t(Category::Process);
  const auto band = process_band_reference(cats, 10);
  for (int x = 0; x < 30; ++x) EXPECT_EQ(band.at(x, 0) != 0, x >= 2 && x <= 22) << x;
}

TEST(ColourModels, CountOnlyKnownPixelsInTheBand) {
  ImageRGB8 colour(4, 1);
  CategoryImage cats(4, 1);
  ImageGray8 band(4, 1, 255);
  const std::uint8_t px[4][3] = {{255, 0, 0}, {255, 0, 0}, {0, 0, 255}, {0, 0, 255}};
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) colour.at(x, 0, c) = px[x][c];
  cats.at(0, 0) = std::uint8_t(Category::Infront);
  cats.at(1, 0) = std::uint8_t(Category::Process);
  cats.at(2, 0) = std::uint8_t(Category::Behind);
  cats.at(3, 0) = std::uint8_t(Category::Behind);
  band.at(3, 0) = 0;
  const auto m = colour_histograms_reference(colour, cats, band, 4);
  ASSERT_EQ(m.infront.size(), 64U);
  EXPECT_EQ(m.infront_total(), 1U);
  EXPECT_EQ(m.behind_total(), 1U);
  EXPECT_EQ(m.infront[colour_bin(255, 0, 0, 4)], 1U);
  EXPECT_EQ(m.behind[colour_bin(0, 0, 255, 4)], 1U);
  EXPECT_EQ(colour_bin(255, 0, 0, 4), 48);
  EXPECT_EQ(colour_bin(63, 64, 255, 4), 7);
}

TEST(CvfCost, CategoriesAndColourLikelihoods) {
  ColourModels m{2, std::vector<std::uint32_t>(8, 0), std::vector<std::uint32_t>(8, 0)};
  m.infront[0] = 30;
  m.infront[1] = 10;
  m.behind[1] = 40;
  m.behind[2] = 40;
  EXPECT_EQ(cvf_cost(Category::Infront, 0, m, true, 0, 1), 1.0F);
  EXPECT_EQ(cvf_cost(Category::Behind, 0, m, true, 0, 1), 0.0F);
  EXPECT_EQ(cvf_cost(Category::Ignore, 0, m, true, 0, 0), 0.5F);
  EXPECT_FLOAT_EQ(cvf_cost(Category::Process, 0, m, true, 0, 1000), 1.0F);
  // P_in = 10/40, P_behind = 40/80.
  EXPECT_FLOAT_EQ(cvf_cost(Category::Process, 1, m, true, 0, 1000), 0.25F / 0.75F);
  EXPECT_FLOAT_EQ(cvf_cost(Category::Process, 5, m, true, 0, 1000), 0.5F);
  // Without colour models: the raw depth test, 0.5 where unknown.
  EXPECT_EQ(cvf_cost(Category::Process, 1, m, false, 990, 1000), 1.0F);
  EXPECT_EQ(cvf_cost(Category::Process, 1, m, false, 1000, 1000), 0.0F);
  EXPECT_EQ(cvf_cost(Category::Process, 1, m, false, 0, 1000), 0.5F);
}

// A red disc (real, 600 mm) in front of a blue wall (2000 mm), a virtual plane at 1000 mm over
// the whole image, and depth missing in a ring around the disc: colour must decide the ring.
struct DiscScene {
  ImageRGB8 colour;
  DepthImage depth;
  ImageF virt;
  ImageF truth;  // visibility
};

DiscScene disc_scene(int w, int h, std::uint64_t seed) {
  DiscScene s{ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h, 1000.0F), ImageF(w, h)};
  std::mt19937 rng(static_cast<std::uint32_t>(seed));
  std::normal_distribution<float> n(0.0F, 6.0F);
  const float cx = w * 0.5F, cy = h * 0.5F, R = h * 0.3F;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float d = std::hypot(x - cx, y - cy);
      const bool disc = d < R;
      const std::uint8_t base[3] = {std::uint8_t(disc ? 200 : 30), 40,
                                    std::uint8_t(disc ? 30 : 200)};
      for (int c = 0; c < 3; ++c)
        s.colour.at(x, y, c) =
            static_cast<std::uint8_t>(std::clamp(base[c] + n(rng), 0.0F, 255.0F));
      s.depth.at(x, y) = std::fabs(d - R) < 4.0F ? 0 : disc ? 600 : 2000;
      s.truth.at(x, y) = disc ? 0.0F : 1.0F;
    }
  return s;
}

TEST(CvfReference, ColourDecidesWhereDepthIsMissing) {
  const auto s = disc_scene(96, 64, 1);
  const auto t = cvf_reference(s.colour, s.depth, s.virt);
  EXPECT_TRUE(t.colour_models_valid);
  double err = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 96; ++x) err += std::pow(t.alpha.at(x, y) - s.truth.at(x, y), 2);
  EXPECT_LT(err / (96 * 64), 0.01);
  // Deep inside either region the matte is exact.
  EXPECT_NEAR(t.alpha.at(48, 32), 0.0F, 1e-4);
  EXPECT_NEAR(t.alpha.at(2, 2), 1.0F, 1e-4);
}

TEST(CvfReference, AlphaIsZeroOffTheObject) {
  auto s = disc_scene(40, 30, 2);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 10; ++x) s.virt.at(x, y) = 0.0F;
  const auto t = cvf_reference(s.colour, s.depth, s.virt);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 10; ++x) ASSERT_EQ(t.alpha.at(x, y), 0.0F);
}

}  // namespace
}  // namespace probeless::occlusion
