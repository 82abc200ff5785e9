// Issue #19 item 4: a hand closer than the depth sensor's minimum range has no depth; it must
// still occlude where its colour says so. The same scene with the hand at 0.45 m (the Kinect
// model's minimum range is 0.5 m: no depth) and at 0.6 m (measured), through the Kinect noise
// model (core/depth_noise.hpp); MSE of every CVF and Direct against the true matte.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <ranges>
#include <tuple>
#include <utility>
#include <vector>

#include "core/depth_noise.hpp"
#include "kernels/occlusion/cvf/cvf_local_reference.hpp"
#include "kernels/occlusion/cvf/hole_core.hpp"
#include "kernels/occlusion/cvf/hole_core_reference.hpp"
#include "kernels/occlusion/method_registry.hpp"
#include "support/cl_context.hpp"

namespace probeless::occlusion {
namespace {

using testing::cl_context;

struct NearScene {
  ImageRGB8 colour;
  DepthImage depth;  // through the noise model
  ImageF virt;
  ImageF truth;  // visibility of the object, -1 off it
};

// A textured wall at 2 m, a red mug at 0.9 m in front of the object's lower left, a virtual box
// at 1.2 m, and a hand (palm, fingers, the wrist running out of the frame) at hand_m.
NearScene near_scene(double hand_m, std::uint64_t seed, bool mug = true) {
  const int w = 320, h = 240;
  const double focal = 525.0 * w / 640;
  std::mt19937 rng(7);  // the same colours in both variants
  std::normal_distribution<float> grain(0.0F, 6.0F);
  NearScene s{ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h), ImageF(w, h)};
  DepthImage clean(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool palm = std::hypot((x - 205.0) / 38, (y - 120.0) / 30) < 1;
      const bool finger = x > 150 && x < 205 &&
                          (std::abs(y - 100) < 5 || std::abs(y - 118) < 5 || std::abs(y - 136) < 5);
      const bool wrist = x >= 205 && std::abs(y - 125) < 20;
      const bool hand = palm || finger || wrist;
      const bool is_mug = mug && std::hypot((x - 100.0) / 25, (y - 185.0) / 30) < 1;
      float base[3];
      double z;
      if (hand) {
        const float shade = 0.85F + 0.15F * std::sin(0.08F * float(y));
        base[0] = 205 * shade, base[1] = 150 * shade, base[2] = 125 * shade, z = hand_m;
      } else if (is_mug) {
        base[0] = 160, base[1] = 30, base[2] = 40, z = 0.9;
      } else {
        const bool patch = ((x / 40) + (y / 40)) % 2 == 0;  // two wall tones
        base[0] = patch ? 90.F : 170.F, base[1] = patch ? 110.F : 160.F,
        base[2] = patch ? 140.F : 120.F, z = 2.0;
      }
      for (int c = 0; c < 3; ++c)
        s.colour.at(x, y, c) = std::uint8_t(std::clamp(base[c] + grain(rng), 0.0F, 255.0F));
      clean.at(x, y) = std::uint16_t(std::lround(z * 1000));
      const bool on = x >= 60 && x < 260 && y >= 40 && y < 220;
      s.virt.at(x, y) = on ? 1200.0F : 0.0F;
      s.truth.at(x, y) = on ? (z * 1000 >= 1200 ? 1.0F : 0.0F) : -1.0F;
    }
  s.depth = apply_kinect_noise(clean, focal, seed);
  return s;
}

double mse(const ImageF& alpha, const ImageF& truth) {
  double sum = 0;
  int n = 0;
  for (int y = 0; y < truth.height(); ++y)
    for (int x = 0; x < truth.width(); ++x) {
      if (truth.at(x, y) < 0) continue;
      const double d = alpha.at(x, y) - truth.at(x, y);
      sum += d * d;
      ++n;
    }
  return sum / n;
}

struct Mses {
  double device, reference;
};

// hole_core_px < 0: the shipped default.
Mses run(const NearScene& s, const std::string& method, bool near_occluders = false,
         int hole_core_px = -1) {
  auto& ctx = cl_context();
  MethodParams params;
  params.cvf.near_occluders = near_occluders;
  if (hole_core_px >= 0) params.cvf.hole_core_px = hole_core_px;
  auto m = make_method(ctx, method, params);
  const DeviceImageRGB8 colour(ctx, s.colour);
  const DeviceImage<std::uint16_t, 1> real(ctx, s.depth);
  const DeviceImageF virt(ctx, s.virt);
  DeviceImageF alpha;
  m->process({&colour, &real, &virt}, alpha);
  Mses out{mse(alpha.download(ctx.queue()), s.truth), -1};
  if (method == "cvf") {
    CvfLocalParams p;
    p.near_occluders = near_occluders;
    if (hole_core_px >= 0) p.hole_core_px = hole_core_px;
    out.reference = mse(cvf_local_reference(s.colour, s.depth, s.virt, p).alpha, s.truth);
  }
  return out;
}

// The hand without depth (a) and with depth (b), device and reference, x1e3.
void print_pair(const char* label, bool mug, const Mses& a, const Mses& b) {
  std::printf(
      "%s mug=%d: without depth %.2f (reference %.2f), with depth %.2f (reference %.2f), "
      "ratio %.2f\n",
      label, int(mug), 1e3 * a.device, 1e3 * a.reference, 1e3 * b.device, 1e3 * b.reference,
      a.device / b.device);
}

// Prints every method's MSE with the hand at 0.45 m (no depth) and 0.6 m (depth), and cvf
// without hole cores, with and without the near-occluder cap (near_occluder_reference.hpp, the
// variant measured before the hole cores and left off). Asserts what the cap achieves: the hand
// without depth at < 0.3x the MSE without the cap, the hand with depth not worse, device and
// reference alike. The cap alone misses the bar (13-24x; docs/occlusion.md).
TEST(NearOccluder, ColourCapHidesAHandWithoutDepth) {
  for (const bool mug : {true, false}) {
    const auto near = near_scene(0.45, 11, mug), far = near_scene(0.60, 11, mug);
    int holes = 0, hand = 0;
    for (int y = 0; y < 240; ++y)
      for (int x = 0; x < 320; ++x)
        if (near.truth.at(x, y) == 0.0F && near.colour.at(x, y, 0) > 150 &&
            near.colour.at(x, y, 2) > 90) {
          ++hand;
          holes += near.depth.at(x, y) == 0;
        }
    ASSERT_GT(holes, 0.95 * hand) << "the noise model must drop the near hand's depth";
    for (const char* method : {"cvf", "cvf_thesis", "direct1", "direct2", "bilateral"}) {
      const auto a = run(near, method), b = run(far, method);
      std::printf("%s mug=%d: MSE x1e3 without depth %.2f, with depth %.2f (ratio %.2f)\n", method,
                  int(mug), 1e3 * a.device, 1e3 * b.device, a.device / b.device);
    }
    const auto a0 = run(near, "cvf", false, 0), b0 = run(far, "cvf", false, 0);
    const auto a = run(near, "cvf", true, 0), b = run(far, "cvf", true, 0);
    print_pair("cvf + near cap", mug, a, b);
    EXPECT_LT(a.device, 0.3 * a0.device) << "mug " << mug;
    EXPECT_LT(a.reference, 0.3 * a0.reference) << "mug " << mug;
    EXPECT_LE(b.device, b0.device * 1.02) << "mug " << mug;
    if (mug) {  // with a valid colour pair, device and reference agree (see below otherwise)
      EXPECT_NEAR(a.device, a.reference, 1e-4);
      EXPECT_NEAR(b.device, b.reference, 1e-4);
    }
  }
}

// A hole is a near occluder where its clipped (2r+1)^2 window is all hole: a 12x12 hole's
// centre at r = 3, not a 6 px sliver, and a hole at the frame's edge through the clipping.
TEST(HoleCore, ReferenceFillsOnlyTheCoresOfWideHoles) {
  DepthImage d(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const bool square = x >= 4 && x < 16 && y >= 4 && y < 16;
      const bool sliver = x >= 24 && x < 30 && y >= 2 && y < 28;
      const bool edge = x >= 34 && y >= 20;  // 6 x 10, leaving the frame right and bottom
      d.at(x, y) = square || sliver || edge ? 0 : 2000;
    }
  const auto f = fill_hole_cores_reference(d, 3);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const bool core = (x >= 7 && x < 13 && y >= 7 && y < 13) || (x >= 37 && y >= 23);
      EXPECT_EQ(f.at(x, y), core ? kNearHoleDepthMm : d.at(x, y)) << x << "," << y;
    }
  const auto unchanged = fill_hole_cores_reference(d, 0);
  const auto a = unchanged.elements();
  const auto b = std::as_const(d).elements();
  EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end()));
}

// The whole near occluder is marked for the stages after the matte: the 12x12 hole of the
// reference test above entirely (its core is within r of every pixel of it), the 6 px sliver
// not at all (no core), depth never.
TEST(HoleCore, ReferenceMarksTheRimAroundACore) {
  DepthImage d(40, 30, std::uint16_t{2000});
  for (int y = 4; y < 16; ++y)
    for (int x = 4; x < 16; ++x) d.at(x, y) = 0;
  for (int y = 2; y < 28; ++y)
    for (int x = 24; x < 30; ++x) d.at(x, y) = 0;
  const auto m = mark_near_occluders_reference(d, 3);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const bool square = x >= 4 && x < 16 && y >= 4 && y < 16;
      EXPECT_EQ(m.at(x, y), square ? kNearHoleDepthMm : d.at(x, y)) << x << "," << y;
    }
}

// The rim follows the occluder: a hand-coloured hole with a core, its rim (holes of its colour,
// beside measured wall on one side) and on the other a band of wall-coloured holes 4 px wide
// (what the Kinect's window rule leaves beside a depth edge). With the colour only the hand's holes
// are marked; without, every hole within r of the core, the wall's band too. Device = reference.
TEST(HoleCore, TheRimTakesTheCoresColourNotTheWalls) {
  const int w = 640, h = 60, r = 8;  // 640 px: the measured window's radius is 4 px
  DepthImage d(w, h, std::uint16_t{2000});
  ImageRGB8 c(w, h);
  const std::uint8_t wall[3] = {170, 160, 120}, skin[3] = {205, 150, 125};
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> grain(-6, 6);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool hand = x >= 30 && x < 70;
      const bool wall_band = x >= 70 && x < 74;  // wall holes beside the hand's edge
      if (hand || wall_band) d.at(x, y) = 0;
      const std::uint8_t* base = hand ? skin : wall;
      for (int k = 0; k < 3; ++k)
        c.at(x, y, k) = static_cast<std::uint8_t>(std::clamp(base[k] + grain(rng), 0, 255));
    }
  const DepthImage cores = fill_hole_cores_reference(d, r, &c);
  const DepthImage old_rule = mark_near_occluders_reference(d, r);
  const DepthImage rim = mark_near_occluders_reference(d, r, &c);
  int hand_rim = 0, hand_rim_marked = 0, band = 0, band_old = 0, band_marked = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (d.at(x, y) != 0 || cores.at(x, y) == kNearHoleDepthMm) continue;
      if (x < 70) ++hand_rim, hand_rim_marked += rim.at(x, y) == kNearHoleDepthMm;
      if (x >= 70)
        ++band, band_old += old_rule.at(x, y) == kNearHoleDepthMm,
            band_marked += rim.at(x, y) == kNearHoleDepthMm;
    }
  ASSERT_GT(hand_rim, 100);
  ASSERT_EQ(band, 4 * h);
  EXPECT_EQ(band_old, band) << "without colour the wall's band is marked as the hand";
  EXPECT_EQ(band_marked, 0) << "with colour it is not";
  EXPECT_EQ(hand_rim_marked, hand_rim) << "the hand's own rim is";
  auto& ctx = cl_context();
  HoleCoreFill fill(ctx);
  const DeviceImage<std::uint16_t, 1> depth_dev(ctx, d);
  const DeviceImageRGB8 colour_dev(ctx, c);
  fill.run(depth_dev, r, &colour_dev);
  EXPECT_TRUE(std::ranges::equal(
      fill.mark_near_occluders(&colour_dev).download(ctx.queue()).elements(), rim.elements()));
}

TEST(HoleCore, DeviceEqualsReference) {
  auto& ctx = cl_context();
  for (const int r : {1, 4, 9}) {
    const auto s = near_scene(0.45, 5);
    HoleCoreFill fill(ctx);
    const DeviceImage<std::uint16_t, 1> real(ctx, s.depth);
    const auto got = fill.run(real, r).download(ctx.queue());
    const auto want = fill_hole_cores_reference(s.depth, r);
    const auto g = got.elements(), e = want.elements();
    ASSERT_TRUE(std::equal(g.begin(), g.end(), e.begin(), e.end())) << "r " << r;
    const auto got_marked = fill.mark_near_occluders().download(ctx.queue());
    const auto want_marked = mark_near_occluders_reference(s.depth, r);
    const auto gm = got_marked.elements(), em = want_marked.elements();
    ASSERT_TRUE(std::equal(gm.begin(), gm.end(), em.begin(), em.end())) << "marked, r " << r;
    EXPECT_GT(std::count(em.begin(), em.end(), kNearHoleDepthMm),
              std::count(e.begin(), e.end(), kNearHoleDepthMm))
        << "the rim is marked besides the core, r " << r;
    // With the colour: the rim that takes the core's colour.
    const DeviceImageRGB8 colour(ctx, s.colour);
    fill.run(real, r, &colour);
    const auto got_rim = fill.mark_near_occluders(&colour).download(ctx.queue());
    const auto want_rim = mark_near_occluders_reference(s.depth, r, &s.colour);
    ASSERT_TRUE(std::ranges::equal(got_rim.elements(), want_rim.elements())) << "rim, r " << r;
    EXPECT_GT(std::ranges::count(want_rim.elements(), kNearHoleDepthMm),
              std::count(e.begin(), e.end(), kNearHoleDepthMm))
        << "the hand's rim is marked besides the core, r " << r;
  }
  // A width that is no multiple of the column pass's 16 lanes.
  const auto s = near_scene(0.45, 6);
  DepthImage odd(317, 211);
  for (int y = 0; y < odd.height(); ++y)
    for (int x = 0; x < odd.width(); ++x) odd.at(x, y) = s.depth.at(x, y);
  HoleCoreFill fill_odd(ctx);
  const DeviceImage<std::uint16_t, 1> odd_dev(ctx, odd);
  const auto got = fill_odd.run(odd_dev, 7).download(ctx.queue());
  const auto want = fill_hole_cores_reference(odd, 7);
  int last_group_cores = 0;  // the wrist leaves the frame there: the partial group is tested
  for (int y = 0; y < odd.height(); ++y)
    for (int x = 304; x < odd.width(); ++x) last_group_cores += want.at(x, y) == kNearHoleDepthMm;
  EXPECT_GT(last_group_cores, 100);
  const auto g = got.elements(), e = want.elements();
  EXPECT_TRUE(std::equal(g.begin(), g.end(), e.begin(), e.end()));
  {  // The rim with colour, over the whole frame and inside a rectangle (CVF's objects').
    ImageRGB8 odd_colour(odd.width(), odd.height());
    for (int y = 0; y < odd.height(); ++y)
      for (int x = 0; x < odd.width(); ++x)
        for (int c = 0; c < 3; ++c) odd_colour.at(x, y, c) = s.colour.at(x, y, c);
    const DeviceImageRGB8 colour(ctx, odd_colour);
    const auto want_rim = mark_near_occluders_reference(odd, 7, &odd_colour);
    fill_odd.run(odd_dev, 7, &colour);
    EXPECT_TRUE(
        std::ranges::equal(fill_odd.mark_near_occluders(&colour).download(ctx.queue()).elements(),
                           want_rim.elements()));
    const PixelRect rect{101, 37, 298, 190};
    fill_odd.run(odd_dev, 7, &colour, rect);
    const auto got_rect = fill_odd.mark_near_occluders(&colour).download(ctx.queue());
    int differ = 0;
    for (int y = rect.y0; y < rect.y1; ++y)
      for (int x = rect.x0; x < rect.x1; ++x) differ += got_rect.at(x, y) != want_rim.at(x, y);
    EXPECT_EQ(differ, 0) << "inside the rectangle";
  }
  HoleCoreFill fill(ctx);
  const DeviceImage<std::uint16_t, 1> real(ctx, near_scene(0.45, 5).depth);
  EXPECT_THROW(fill.run(real, 0), std::invalid_argument);
}

// The bar with the shipped cvf (hole cores on): the hand without depth matted within 2x
// of the same hand with depth, device equal to the reference; and far better than without the
// cores (88e-3 and 69e-3 then).
// The row pass works on bit sets, 64 pixels a word, with r pixels of margin each side, and
// falls back to a sliding count past 4096 px with the margins: radii across word boundaries
// (63, 64, 65 and 150: a step of more than a word), widths that are no multiple of 64, and a
// row too wide for the bit sets, on random holes with wide blobs.
TEST(HoleCore, DeviceEqualsReferenceAtWideRadiiAndRows) {
  auto& ctx = cl_context();
  std::mt19937 rng(11);
  auto random_depth = [&](int w, int h) {
    DepthImage d(w, h);
    for (auto& v : d.elements()) v = rng() % 3 == 0 ? 0 : 1200;
    for (int blob = 0; blob < 4; ++blob) {
      const int x0 = static_cast<int>(rng() % w), bw = 20 + static_cast<int>(rng() % 300);
      for (int y = 0; y < h; ++y)
        for (int x = x0; x < std::min(w, x0 + bw); ++x) d.at(x, y) = 0;
    }
    return d;
  };
  for (const auto& [w, h, r] : std::vector<std::tuple<int, int, int>>{{700, 12, 63},
                                                                      {700, 12, 64},
                                                                      {700, 12, 65},
                                                                      {700, 9, 150},
                                                                      {65, 70, 20},
                                                                      {3990, 3, 20},
                                                                      {4200, 3, 5}}) {
    const DepthImage d = random_depth(w, h);
    HoleCoreFill fill(ctx);
    const DeviceImage<std::uint16_t, 1> real(ctx, d);
    const auto got = fill.run(real, r).download(ctx.queue());
    const auto want = fill_hole_cores_reference(d, r);
    EXPECT_TRUE(std::ranges::equal(got.elements(), want.elements())) << w << "x" << h << " r " << r;
    EXPECT_GT(std::ranges::count(want.elements(), kNearHoleDepthMm), 0) << w << " r " << r;
    const auto got_marked = fill.mark_near_occluders().download(ctx.queue());
    const auto want_marked = mark_near_occluders_reference(d, r);
    EXPECT_TRUE(std::ranges::equal(got_marked.elements(), want_marked.elements()))
        << "marked, " << w << "x" << h << " r " << r;
    // With random colours (the rim's row sums and the decision at every radius; 16-bit sums
    // take r <= 128).
    if (r > 128) continue;
    ImageRGB8 c(w, h);
    for (auto& v : c.elements()) v = static_cast<std::uint8_t>(rng());
    const DeviceImageRGB8 colour(ctx, c);
    fill.run(real, r, &colour);
    const auto got_rim = fill.mark_near_occluders(&colour).download(ctx.queue());
    EXPECT_TRUE(
        std::ranges::equal(got_rim.elements(), mark_near_occluders_reference(d, r, &c).elements()))
        << "rim, " << w << "x" << h << " r " << r;
  }
}

// A sunlit window and a black screen are wide holes too (the sim's room has both): with the
// colour frame, holes of those colours are no core candidates, while a skin-coloured hole of
// the same size still is; the device equals the reference with the colour, on the bit sets and
// on the sliding count of rows too wide for them.
TEST(HoleCore, WindowsAndBlackScreensAreNoCores) {
  auto& ctx = cl_context();
  for (const int w : {240, 4200}) {
    const int h = 60;
    DepthImage d(w, h);
    ImageRGB8 c(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        d.at(x, y) = 1500;
        const std::uint8_t wall[3] = {150, 140, 120};
        for (int k = 0; k < 3; ++k) c.at(x, y, k) = wall[k];
      }
    // Three 50x50 holes: white (a window), black (a screen), skin (a hand without depth).
    const std::uint8_t colours[3][3] = {{250, 252, 255}, {20, 22, 30}, {205, 150, 120}};
    for (int k = 0; k < 3; ++k)
      for (int y = 5; y < 55; ++y)
        for (int x = 10 + 70 * k; x < 60 + 70 * k; ++x) {
          d.at(x, y) = 0;
          for (int ch = 0; ch < 3; ++ch) c.at(x, y, ch) = colours[k][ch];
        }
    const int r = 10;
    const DepthImage want = fill_hole_cores_reference(d, r, &c);
    auto cores_in = [&](const DepthImage& img, int k) {
      int n = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 10 + 70 * k; x < 60 + 70 * k; ++x) n += img.at(x, y) == kNearHoleDepthMm;
      return n;
    };
    EXPECT_EQ(cores_in(want, 0), 0) << "white, w " << w;
    EXPECT_EQ(cores_in(want, 1), 0) << "black, w " << w;
    EXPECT_GT(cores_in(want, 2), 100) << "skin, w " << w;
    EXPECT_GT(cores_in(fill_hole_cores_reference(d, r), 0), 100) << "without colour, w " << w;
    const DeviceImage<std::uint16_t, 1> depth_dev(ctx, d);
    const DeviceImage<std::uint8_t, 3> colour_dev(ctx, c);
    HoleCoreFill fill(ctx);
    const auto got = fill.run(depth_dev, r, &colour_dev).download(ctx.queue());
    EXPECT_TRUE(std::ranges::equal(got.elements(), want.elements())) << "w " << w;
    const auto marked = fill.mark_near_occluders(&colour_dev).download(ctx.queue());
    EXPECT_TRUE(
        std::ranges::equal(marked.elements(), mark_near_occluders_reference(d, r, &c).elements()))
        << "marked, w " << w;
  }
}

TEST(HoleCore, HandWithoutDepthWithinTwiceWithDepth) {
  ASSERT_GT(CvfLocalParams{}.hole_core_px, 0) << "the shipped cvf takes hole cores";
  for (const bool mug : {true, false}) {
    const auto near = near_scene(0.45, 11, mug), far = near_scene(0.60, 11, mug);
    const auto a = run(near, "cvf"), b = run(far, "cvf");
    print_pair("cvf (hole cores)", mug, a, b);
    EXPECT_LE(a.device, 2.0 * b.device) << "mug " << mug;
    EXPECT_LT(a.device, 3e-3) << "mug " << mug;
    EXPECT_NEAR(a.device, a.reference, 1e-4) << "mug " << mug;
    EXPECT_NEAR(b.device, b.reference, 1e-4) << "mug " << mug;
  }
}

// What the matte judged by is what the stages after it (the stabiliser) are given: the filled
// depth with hole cores, the sensor's without.
TEST(HoleCore, JudgedDepthIsTheFilledOne) {
  auto& ctx = cl_context();
  const auto s = near_scene(0.45, 11);
  const DeviceImageRGB8 colour(ctx, s.colour);
  const DeviceImage<std::uint16_t, 1> real(ctx, s.depth);
  const DeviceImageF virt(ctx, s.virt);
  const OcclusionInputs in{&colour, &real, &virt};
  DeviceImageF alpha;
  auto shipped = make_method(ctx, "cvf");
  shipped->process(in, alpha);
  const auto* judged = shipped->as_judged(in).real_depth_mm;
  ASSERT_NE(judged, &real);
  ASSERT_EQ(judged, shipped->judged_depth());
  const auto got = judged->download(ctx.queue());
  const auto want = mark_near_occluders_reference(
      s.depth, hole_core_radius(CvfLocalParams{}.hole_core_px, 320), &s.colour);
  const auto g = got.elements(), e = want.elements();
  EXPECT_TRUE(std::equal(g.begin(), g.end(), e.begin(), e.end()));
  EXPECT_GT(std::count(e.begin(), e.end(), kNearHoleDepthMm), 2000) << "the hand has a core";
  MethodParams off;
  off.cvf.hole_core_px = 0;
  auto plain = make_method(ctx, "cvf", off);
  plain->process(in, alpha);
  EXPECT_EQ(plain->judged_depth(), nullptr);
  EXPECT_EQ(plain->as_judged(in).real_depth_mm, &real);
  EXPECT_EQ(make_method(ctx, "direct1")->as_judged(in).real_depth_mm, &real);
}

// The matting protocol's unknown region is a trimap's, not a near surface: no hole cores there.
TEST(HoleCore, ExactTrimapTakesNone) {
  MethodParams p;
  ASSERT_GT(p.cvf.hole_core_px, 0);
  use_exact_trimap(p);
  EXPECT_EQ(p.cvf.hole_core_px, 0);
  EXPECT_EQ(p.categorise.erosion_px, 0);
}

// Cost at 640x480 (run by hand: --gtest_also_run_disabled_tests): median of 100 runs.
TEST(HoleCore, DISABLED_CostVga) {
  auto& ctx = cl_context();
  DepthImage d(640, 480);
  std::mt19937 rng(3);
  for (auto& v : d.elements()) v = rng() % 4 == 0 ? 0 : 1500;
  for (int y = 100; y < 400; ++y)
    for (int x = 300; x < 640; ++x) d.at(x, y) = 0;
  const DeviceImage<std::uint16_t, 1> real(ctx, d);
  ImageRGB8 c(640, 480);
  for (auto& v : c.elements()) v = static_cast<std::uint8_t>(rng());
  const DeviceImageRGB8 colour(ctx, c);
  HoleCoreFill fill(ctx);
  // The cores alone, then with the rim that takes their colour (what cvf runs), then with the
  // rim marked by the rule without colour.
  for (const int variant : {0, 1, 2}) {
    std::vector<double> ms;
    for (int i = 0; i < 120; ++i) {
      ctx.queue().finish();
      const auto t0 = std::chrono::steady_clock::now();
      fill.run(real, 20, &colour);
      if (variant == 1) fill.mark_near_occluders(&colour);
      if (variant == 2) fill.mark_near_occluders();
      ctx.queue().finish();
      if (i >= 20)
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
    }
    std::sort(ms.begin(), ms.end());
    std::printf("hole cores 640x480 r=20%s: p50 %.3f ms\n",
                variant == 1   ? " + the rim by colour"
                : variant == 2 ? " + the rim without colour"
                               : "",
                ms[ms.size() / 2]);
  }
}

}  // namespace
}  // namespace probeless::occlusion
