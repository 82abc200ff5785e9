// The shipped CVF ("cvf": local colour models, local prior, softness) end to end on the device
// against its CPU reference, intermediate by intermediate, in both layouts (row-streaming
// strips for CPUs, tiles for GPUs), on synthetic scenes of odd sizes and on real Middlebury
// frames with the Kinect noise model.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/occlusion/cvf/cvf_local_reference.hpp"
#include "kernels/occlusion/cvf/cvf_matte.hpp"
#include "kernels/occlusion/cvf/cvf_reference.hpp"
#include "kernels/occlusion/method_registry.hpp"
#include "lab/eval/middlebury_dataset.hpp"
#include "support/cl_context.hpp"
#include "support/test_data.hpp"

namespace probeless::occlusion {
namespace {

struct Scene {
  ImageRGB8 colour;
  DepthImage depth;
  ImageF virt;
};

// A near disc and a far wall whose colours overlap on one side of the frame (so the frame's
// two colour models overlap and softness matters) and differ on the other (so the tiles'
// models differ from the frame's); holes along the disc's edge and scattered; a virtual disc
// plus a slanted plane through both.
Scene random_scene(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  std::normal_distribution<float> n(0.0F, 10.0F);
  Scene s{ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h)};
  const float cx = w * u(rng), cy = h * u(rng), r = 0.3F * std::min(w, h) + 2;
  const float bx = w * u(rng), by = h * u(rng);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float d = std::hypot(x - cx, y - cy);
      const bool fg = d < r;
      const bool near_edge = std::fabs(d - r) < 2.5F;
      const bool left = x < w / 2;
      const std::uint8_t base[3] = {std::uint8_t(fg || left ? 150 : 40), std::uint8_t(90),
                                    std::uint8_t(fg && !left ? 50 : 140)};
      for (int c = 0; c < 3; ++c)
        s.colour.at(x, y, c) = std::uint8_t(std::clamp(base[c] + n(rng), 0.0F, 255.0F));
      const float z = fg ? 800.0F + 2.0F * (y - cy) : 2200.0F;
      s.depth.at(x, y) = near_edge || u(rng) < 0.03F ? 0 : std::uint16_t(z + n(rng));
      const bool on = (x > bx * 0.3F) || std::hypot(x - bx, y - by) < r;
      s.virt.at(x, y) = on ? 1200.0F + 3.0F * x : 0.0F;
    }
  return s;
}

// Device vs reference. Returns the number of process pixels with softness > 0.05 in the
// reference (so callers can insist that the soft path ran).
int expect_matches(const Scene& s, const CvfLocalParams& params, CvfLayout layout,
                   const std::string& what) {
  SCOPED_TRACE(::testing::Message() << what << " " << s.colour.width() << "x" << s.colour.height()
                                    << " layout " << int(layout));
  auto& ctx = testing::cl_context();
  const auto ref = cvf_local_reference(s.colour, s.depth, s.virt, params);
  CvfMatte cvf(ctx, params, /*trace=*/true, layout);
  EXPECT_EQ(cvf.name(), "cvf");
  EXPECT_EQ(cvf.layout(), layout);
  DeviceImageRGB8 colour(ctx, s.colour);
  DeviceDepthImage depth(ctx, s.depth);
  DeviceImageF virt(ctx, s.virt), alpha;
  cvf.process({&colour, &depth, &virt}, alpha);
  const auto got = alpha.download(ctx.queue());
  const auto t = cvf.download_trace();
  const int w = s.colour.width(), h = s.colour.height();

  EXPECT_EQ(t.categories, ref.categories);
  for (std::size_t i = 0; i < t.band.elements().size(); ++i)
    EXPECT_EQ(t.band.elements()[i] != 0, ref.band.elements()[i] != 0) << i;
  EXPECT_EQ(t.models.infront, ref.global.infront);
  EXPECT_EQ(t.models.behind, ref.global.behind);
  const auto tiles = tile_histograms_reference(s.colour, ref.categories, ref.band,
                                               params.cvf.bins_per_channel, params.tile_px);
  EXPECT_EQ(t.tiles.infront, tiles.infront);
  EXPECT_EQ(t.tiles.behind, tiles.behind);
  EXPECT_EQ(t.tiles.infront_total, tiles.infront_total);

  // The wide filter's input is the cost itself at full resolution (block averages else).
  int soft = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (params.cvf.wide.subsample == 1) {
        EXPECT_NEAR(t.wide_input.at(x, y, 3), ref.cost.at(x, y), 1e-4) << x << "," << y;
      }
      if (ref.softness.at(x, y) > 0.05F) ++soft;
    }
  // The hard part of the threshold may flip where the wide filter's output is within float
  // noise of 0.5; elsewhere the mask (hard and soft) agrees.
  int flips = 0, undecided = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool near_half = std::fabs(ref.wide.at(x, y) - 0.5F) < 1e-3F;
      if (near_half) ++undecided;
      if (std::fabs(t.feather_input.at(x, y, 3) - ref.mask.at(x, y)) > 1e-3F) {
        ++flips;
        EXPECT_TRUE(near_half) << x << "," << y << ": mask " << t.feather_input.at(x, y, 3)
                               << " vs " << ref.mask.at(x, y) << ", wide " << ref.wide.at(x, y);
      }
    }
  EXPECT_LE(flips, undecided);
  int far = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (std::fabs(got.at(x, y) - ref.alpha.at(x, y)) > 1e-3F) ++far;
  EXPECT_LE(far, 25 * flips) << "alpha differs on " << far << " pixels";
  return soft;
}

void expect_matches_both(const Scene& s, const CvfLocalParams& p, const std::string& what) {
  expect_matches(s, p, CvfLayout::Strips, what);
  expect_matches(s, p, CvfLayout::Tiles, what);
}

TEST(CvfShippedDevice, MatchesReferenceOnSyntheticScenes) {
  const CvfLocalParams p;
  const int sizes[][2] = {{97, 61}, {131, 9}, {64, 48}, {160, 121}};
  std::uint32_t seed = 1;
  int soft = 0;
  for (const auto& sz : sizes) {
    const auto s = random_scene(sz[0], sz[1], seed++);
    soft += expect_matches(s, p, CvfLayout::Strips, "defaults");
    expect_matches(s, p, CvfLayout::Tiles, "defaults");
  }
  EXPECT_GT(soft, 50) << "the scenes must exercise the soft threshold";
}

// Tall frames in several strips (each warms up on rows above it), tiles that straddle the
// strips, and every parameter the kernels specialise on.
TEST(CvfShippedDevice, MatchesReferenceAcrossStripsTilesAndParameters) {
  CvfLocalParams p;
  expect_matches_both(random_scene(70, 250, 8), p, "tall");
  p.tile_px = 7;
  expect_matches_both(random_scene(45, 199, 9), p, "tile 7");
  p.tile_px = 46;
  p.cvf.bins_per_channel = 8;
  expect_matches_both(random_scene(81, 130, 10), p, "tile 46, 8 bins");
  p = {};
  p.prior_radius = 0;
  expect_matches_both(random_scene(75, 40, 11), p, "no prior");
  p.prior_radius = 7;
  p.cvf.band_px = 2;  // the prior reaches farther than the band
  expect_matches_both(random_scene(75, 90, 12), p, "prior 7, band 2");
  p = {};
  p.soft_where_ambiguous = false;
  expect_matches_both(random_scene(66, 50, 13), p, "hard threshold");
  p = {};
  p.cvf.categorise.erosion_px = 0;  // the matting protocol
  expect_matches_both(random_scene(90, 70, 14), p, "erosion 0");
  p.cvf.band_px = 0;
  expect_matches_both(random_scene(90, 70, 15), p, "band 0");
  p = {};
  p.cvf.wide.subsample = 2;
  expect_matches(random_scene(97, 61, 16), p, CvfLayout::Strips, "fast wide filter");
}

// Without a trace the strip filters skip pixels whose windows see no object (cvf_guided.cl,
// object_columns()); alpha must still be the reference's everywhere. The object is a block of
// rows and columns and a disc, so that strips hold several spans, skipped rows between them
// and skipped columns beside them.
TEST(CvfShippedDevice, SkipsPixelsFarFromTheObjectExactly) {
  auto& ctx = testing::cl_context();
  for (const bool thesis : {false, true}) {
    for (const int subsample : {1, 2}) {
      auto s = random_scene(150, 230, 21);
      for (int y = 0; y < s.virt.height(); ++y)
        for (int x = 0; x < s.virt.width(); ++x) {
          const bool band = y >= 30 && y < 61 && x >= 37 && x < 111;
          const bool disc = std::hypot(x - 70.0F, y - 170.0F) < 12.0F;
          if (!band && !disc) s.virt.at(x, y) = 0.0F;
          // A real surface in front over the block's top: the wide filter carries its cost
          // beyond the object's outline, which the feather reads there.
          if (y < 45 && s.depth.at(x, y) != 0) s.depth.at(x, y) = 500;
        }
      CvfLocalParams lp;
      lp.cvf.wide.subsample = subsample;
      CvfParams tp;
      tp.wide.subsample = subsample;
      const auto want = thesis ? cvf_reference(s.colour, s.depth, s.virt, tp).alpha
                               : cvf_local_reference(s.colour, s.depth, s.virt, lp).alpha;
      auto cvf = thesis ? std::make_unique<CvfMatte>(ctx, tp, false, CvfLayout::Strips)
                        : std::make_unique<CvfMatte>(ctx, lp, false, CvfLayout::Strips);
      DeviceImageRGB8 colour(ctx, s.colour);
      DeviceDepthImage depth(ctx, s.depth);
      DeviceImageF virt(ctx, s.virt), alpha;
      // Garbage in the output first: skipped rows must be written, not left.
      alpha.upload(ctx.queue(), ImageF(s.virt.width(), s.virt.height(), 7.0F));
      cvf->process({&colour, &depth, &virt}, alpha);
      const auto got = alpha.download(ctx.queue());
      int far = 0, on = 0;
      for (int y = 0; y < got.height(); ++y)
        for (int x = 0; x < got.width(); ++x) {
          if (std::fabs(got.at(x, y) - want.at(x, y)) > 1e-3F) ++far;
          if (want.at(x, y) > 0.0F) ++on;
        }
      // A threshold may flip within float noise of 0.5; a window cut short would differ on
      // the block's top edge (163 pixels with the wide filter's reach set to 0).
      EXPECT_LE(far, 3) << (thesis ? "cvf_thesis" : "cvf") << " subsample " << subsample;
      EXPECT_GT(on, 1000);
    }
  }
}

TEST(CvfShippedDevice, FallsBackToTheDepthTestWithFewSamples) {
  CvfLocalParams p;
  p.cvf.min_samples = 1000000;
  EXPECT_EQ(expect_matches(random_scene(50, 30, 7), p, CvfLayout::Strips, "few samples"), 0);
  expect_matches(random_scene(50, 30, 7), p, CvfLayout::Tiles, "few samples");
}

// Real frames: the plane patch and the sphere of two Middlebury scenes at full size, one
// Kinect-noise frame each (docs/occlusion.md "Evaluation").
TEST(CvfShippedDevice, MatchesReferenceOnMiddleburyFrames) {
  PROBELESS_REQUIRE_DATA("middlebury");
  const auto root = testing::shared_data_dir() / "middlebury";
  int cases = 0;
  for (const char* scene : {"v2/cones", "2014q/Adirondack"}) {
    if (!std::filesystem::exists(root / scene)) continue;
    const auto stereo = eval::load_middlebury_scene(root / scene);
    for (const auto& c : eval::middlebury_cases(stereo, {1, 1})) {
      const auto& f = c.frames.front();
      const Scene s{f.colour, f.real_depth_mm, f.virtual_depth_mm};
      EXPECT_GT(expect_matches(s, CvfLocalParams{}, CvfLayout::Strips, c.name), 0);
      ++cases;
    }
  }
  if (cases == 0) GTEST_SKIP() << "no v2/cones or 2014q/Adirondack under " << root;
}

TEST(CvfShippedDevice, RejectsWhatTheDeviceCannotRun) {
  auto& ctx = testing::cl_context();
  CvfLocalParams p;
  p.tile_px = 0;
  EXPECT_THROW(CvfMatte(ctx, p), std::invalid_argument);
  p = {};
  p.cvf.bins_per_channel = 9;
  EXPECT_THROW(CvfMatte(ctx, p), std::invalid_argument);
  p = {};
  p.prior_radius = 8;
  EXPECT_THROW(CvfMatte(ctx, p), std::invalid_argument);
  p = {};
  p.cvf.band_px = 17;
  EXPECT_THROW(CvfMatte(ctx, p, false, CvfLayout::Strips), std::invalid_argument);
}

// The registry's "cvf" is this stage with the shared categorise parameters (so the matting
// protocol's erosion 0 reaches it); "cvf_thesis" is the thesis's CVF.
TEST(CvfShippedDevice, RegistryMakesTheShippedStageAndTheThesisBaseline) {
  auto& ctx = testing::cl_context();
  const auto s = random_scene(61, 37, 9);
  MethodParams params;
  params.categorise.erosion_px = 0;
  auto method = make_method(ctx, "cvf", params);
  ASSERT_EQ(method->name(), "cvf");
  auto* cvf = dynamic_cast<CvfMatte*>(method.get());
  ASSERT_NE(cvf, nullptr);
  EXPECT_TRUE(cvf->local_models());
  EXPECT_EQ(cvf->params().categorise.erosion_px, 0);
  EXPECT_EQ(cvf->params().wide.radius, 3);
  EXPECT_FLOAT_EQ(cvf->params().feather.eps, 0.0025F);
  DeviceImageRGB8 colour(ctx, s.colour);
  DeviceDepthImage depth(ctx, s.depth);
  DeviceImageF virt(ctx, s.virt), a_local, a_thesis;
  method->process({&colour, &depth, &virt}, a_local);
  auto thesis = make_method(ctx, "cvf_thesis", params);
  ASSERT_EQ(thesis->name(), "cvf_thesis");
  EXPECT_FALSE(dynamic_cast<CvfMatte&>(*thesis).local_models());
  thesis->process({&colour, &depth, &virt}, a_thesis);
  EXPECT_NE(a_local.download(ctx.queue()), a_thesis.download(ctx.queue()))
      << "the two methods must differ on this scene, else the names prove nothing";
}

}  // namespace
}  // namespace probeless::occlusion
