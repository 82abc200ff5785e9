// The HDR surfel map's CPU reference (kernels/fusion/surfel_map_reference.hpp) on ray-cast
// synthetic views: a floor and a box under a camera looking straight down, noise-free, so
// each rule shows alone: correspondence, confidence, the violation removal and the budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "kernels/fusion/surfel_map_reference.hpp"
#include "support/surfel_scenes.hpp"

namespace probeless::fusion {
namespace {

using probeless::testing::AlignedBox;
using probeless::testing::looking_down;
using probeless::testing::render;
using probeless::testing::View;

SurfelIntegrationStats integrate(SurfelMap& map, const View& v, std::int64_t frame) {
  return map.integrate(v.depth, v.colour, {1, 1, 1}, v.k, v.T_world_camera, frame);
}

SurfelMapParams everywhere() {
  SurfelMapParams p;
  p.region_radius_m = 5;
  p.max_surfels = 1000000;  // more than a VGA frame: these tests are not about the budget
  return p;
}

std::size_t count_in(const SurfelMap& map, const AlignedBox& box, double margin) {
  return static_cast<std::size_t>(
      std::count_if(map.surfels().begin(), map.surfels().end(),
                    [&](const Surfel& s) { return box.contains(s.position, margin); }));
}

// The part of a 20 cm box on the floor 2 cm above it: its top and upper sides, not the floor.
const AlignedBox kBox{{-0.1, -0.1, 0.0}, {0.1, 0.1, 0.2}};
const AlignedBox kAboveFloorInBox{{-0.1, -0.1, 0.02}, {0.1, 0.1, 0.2}};

TEST(SurfelMap, AFloorSeenFromTwoPosesFusesToOneSurfelPerPixelNotTwo) {
  SurfelMap map(everywhere());
  const auto first = integrate(map, render(looking_down(0, 0, 1.0), {}), 0);
  EXPECT_EQ(first.fused, 0u);
  EXPECT_EQ(first.born, first.candidates);
  EXPECT_GT(first.born, 290000u) << "640 x 480 less the normal stencil's border";
  // 7 mm across and 0.6 degrees round: every pixel's footprint moves by 2-4 pixels.
  const auto second = integrate(map, render(looking_down(0.007, -0.004, 1.0, 0.01), {}), 1);
  EXPECT_GT(second.fused, 0.97 * static_cast<double>(second.candidates));
  EXPECT_LT(second.born, 0.03 * static_cast<double>(first.born)) << "the newly seen border only";
  EXPECT_LT(static_cast<double>(map.size()), 1.03 * static_cast<double>(first.born));
  // Fused surfels gained confidence and stayed on the floor.
  std::size_t twice = 0;
  for (const Surfel& s : map.surfels()) {
    EXPECT_NEAR(s.position.z(), 0.0f, 0.002f);
    EXPECT_GT(s.normal.z(), 0.999f);
    EXPECT_NEAR(s.radius, std::sqrt(2.0f) * 1.0f / 525.0f, 2e-4f);
    if (s.last_seen_frame == 1 && s.created_frame == 0) {
      ++twice;
      EXPECT_GT(s.confidence, 0.49f);  // two weights, each >= exp(-1 / 0.72) = 0.249
    }
  }
  EXPECT_GT(twice, 280000u);
  EXPECT_EQ(map.stable_count(), 0u) << "two sightings are far from 10";
}

TEST(SurfelMap, ABoxThatAppearsIsInTheMapAtOnceAndStableAfterTenSightings) {
  SurfelMap map(everywhere());
  std::int64_t frame = 0;
  for (; frame < 3; ++frame) integrate(map, render(looking_down(0, 0, 1.0), {}), frame);
  EXPECT_EQ(count_in(map, kAboveFloorInBox, 0.005), 0u);

  const View with_box = render(looking_down(0, 0, 1.0), kBox);
  integrate(map, with_box, frame++);
  const std::size_t on_box = count_in(map, kAboveFloorInBox, 0.005);
  EXPECT_GT(on_box, 15000u) << "its 20 x 20 cm top at 0.8 m: 131 x 131 px less the stencil's";
  for (const Surfel& s : map.surfels())
    if (kAboveFloorInBox.contains(s.position, 0.005)) {
      EXPECT_FALSE(map.is_stable(s));
    }

  int frames_to_stable = 1;
  for (; frames_to_stable < 20; ++frames_to_stable, ++frame) {
    std::size_t stable = 0;
    for (const Surfel& s : map.surfels())
      stable += kAboveFloorInBox.contains(s.position, 0.005) && map.is_stable(s);
    if (stable >= 0.95 * static_cast<double>(on_box)) break;
    integrate(map, with_box, frame);
  }
  std::printf("box: %zu surfels, 95 %% stable after %d frames\n", on_box, frames_to_stable);
  // At the image centre an observation weighs ~1: the tenth makes c_stable = 10.
  EXPECT_GE(frames_to_stable, 10);
  EXPECT_LE(frames_to_stable, 11);
  EXPECT_NEAR(static_cast<double>(count_in(map, kAboveFloorInBox, 0.005)),
              static_cast<double>(on_box), 0.02 * static_cast<double>(on_box))
      << "fused, not duplicated";
}

TEST(SurfelMap, ARemovedBoxLeavesTheMapInOneFrameByTheDepthViolationRule) {
  SurfelMap map(everywhere());
  std::int64_t frame = 0;
  for (; frame < 12; ++frame) integrate(map, render(looking_down(0, 0, 1.0), kBox), frame);
  ASSERT_GT(count_in(map, kAboveFloorInBox, 0.005), 15000u);
  std::size_t stable_on_box = 0;
  for (const Surfel& s : map.surfels())
    stable_on_box += kAboveFloorInBox.contains(s.position, 0.005) && map.is_stable(s);
  ASSERT_GT(stable_on_box, 15000u) << "the box is stable before it goes";

  const auto gone = integrate(map, render(looking_down(0, 0, 1.0), {}), frame);
  EXPECT_EQ(count_in(map, kAboveFloorInBox, 0.005), 0u);
  EXPECT_GT(gone.removed_violation, 15000u);
  EXPECT_GT(gone.born, 10000u) << "the floor it hid, new";
}

TEST(SurfelMap, UnstableSurfelsNotSeenForTwentyFramesAreDeletedStableOnesStay) {
  SurfelMap map(everywhere());
  // A small box seen once (unstable) beside a floor seen 12 times (stable); then the camera
  // looks elsewhere, so nothing is seen or violated. 10 cm tall: a top less than
  // depth_tolerance_m above the floor's surfels would fuse into them.
  const AlignedBox small{{0.3, 0.2, 0.0}, {0.35, 0.25, 0.1}};
  std::int64_t frame = 0;
  for (; frame < 11; ++frame) integrate(map, render(looking_down(0, 0, 1.0), {}), frame);
  integrate(map, render(looking_down(0, 0, 1.0), small), frame++);
  const AlignedBox small_top{{0.3, 0.2, 0.09}, {0.35, 0.25, 0.1}};
  ASSERT_GT(count_in(map, small_top, 0.005), 400u) << "5 x 5 cm at 0.9 m: 29 x 29 px";
  const std::size_t stable = map.stable_count();
  const View away = render(looking_down(5, 5, 1.0), {});
  for (int i = 0; i < 20; ++i) integrate(map, away, frame++);
  EXPECT_GT(count_in(map, small_top, 0.005), 400u) << "20 frames unseen: kept";
  integrate(map, away, frame++);
  EXPECT_EQ(count_in(map, small_top, 0.005), 0u) << "21: deleted";
  // The floor beside it (seen 12 times) stays, and so does whatever of `away` became stable.
  EXPECT_GE(map.stable_count(), stable);
}

TEST(SurfelMap, ClippedPixelsAreFlaggedStartLowerAndColoursAreRadiance) {
  View v = render(looking_down(0, 0, 1.0), {});
  for (int y = 0; y < v.k.height; ++y)
    for (int x = 0; x < v.k.width; ++x) {
      const std::uint8_t level = x < 200 ? 255 : x < 400 ? 1 : 128;
      for (int c = 0; c < 3; ++c) v.colour.at(x, y, c) = level;
    }
  v.colour.at(500, 240, 0) = 255;  // one channel at the ceiling is enough
  SurfelMap map(everywhere());
  map.integrate(v.depth, v.colour, {2.0f, 1.0f, 0.5f}, v.k, v.T_world_camera, 0);
  const float linear = std::pow(128 / 255.0f, 2.2f);
  std::size_t saturated = 0, black = 0, plain = 0;
  for (const Surfel& s : map.surfels()) {
    // Back to the pixel it came from (the camera looks straight down from (0, 0, 1)).
    const int x = static_cast<int>(std::lround(s.position.x() * 525.0 + v.k.cx));
    const int y = static_cast<int>(std::lround(-s.position.y() * 525.0 + v.k.cy));
    if ((x < 200) || (x == 500 && y == 240)) {
      EXPECT_EQ(s.flags, kBornSaturated) << x << "," << y;
      ++saturated;
    } else if (x < 400) {
      EXPECT_EQ(s.flags, kBornBlack) << x << "," << y;
      ++black;
    } else {
      EXPECT_EQ(s.flags, 0) << x << "," << y;
      ++plain;
      EXPECT_NEAR(s.radiance[0], 2.0f * linear, 1e-5f);
      EXPECT_NEAR(s.radiance[2], 0.5f * linear, 1e-5f);
    }
    // exp(-g^2 / 0.72) for the pixel, a quarter of it when clipped.
    const float g = std::hypot(x - 319.5f, y - 239.5f) / 400.0f;
    EXPECT_NEAR(s.confidence, std::exp(-g * g / 0.72f) * (s.flags ? 0.25f : 1.0f), 1e-3f);
  }
  EXPECT_GT(saturated, 50000u);
  EXPECT_GT(black, 50000u);
  EXPECT_GT(plain, 50000u);
}

TEST(SurfelMap, TheBudgetHoldsAndEvictsTheFarthestFirst) {
  SurfelMapParams p = everywhere();
  p.region_centre = {0.3f, 0.1f, 0.0f};
  SurfelMap unbounded(p);
  const View v = render(looking_down(0, 0, 1.0), {});
  integrate(unbounded, v, 0);
  std::vector<float> distance;
  for (const Surfel& s : unbounded.surfels())
    distance.push_back((s.position - p.region_centre).norm());
  std::sort(distance.begin(), distance.end());

  p.max_surfels = 20000;
  SurfelMap map(p);
  const auto stats = integrate(map, v, 0);
  EXPECT_EQ(map.size(), 20000u);
  EXPECT_EQ(stats.evicted, unbounded.size() - 20000u);
  const float kept_limit = distance[20000] + p.eviction_shell_m;
  for (const Surfel& s : map.surfels())
    ASSERT_LE((s.position - p.region_centre).norm(), kept_limit);
  // A second frame fuses into the survivors and evicts the new far ones again; within the last
  // shell the least confident went (the survivors there were seen twice).
  integrate(map, render(looking_down(0.003, 0, 1.0), {}), 1);
  EXPECT_EQ(map.size(), 20000u);
  for (const Surfel& s : map.surfels())
    ASSERT_LE((s.position - p.region_centre).norm(), kept_limit);
}

TEST(SurfelMap, WithinAShellTheLeastConfidentGoFirst) {
  // One frame of floor, the region centred 30 cm right of the view's centre. By distance alone
  // the survivors are a disc around the region's centre; with one shell for everything they
  // are the most confident, a disc around the principal point (the radial weight).
  const auto survivors_mean_x = [](float shell_m) {
    SurfelMapParams p = everywhere();
    p.region_centre = {0.3f, 0.0f, 0.0f};
    p.max_surfels = 20000;
    p.eviction_shell_m = shell_m;
    SurfelMap map(p);
    integrate(map, render(looking_down(0, 0, 1.0), {}), 0);
    double sum = 0;
    for (const Surfel& s : map.surfels()) sum += s.position.x();
    return sum / static_cast<double>(map.size());
  };
  EXPECT_NEAR(survivors_mean_x(0.05f), 0.3, 0.01);
  EXPECT_NEAR(survivors_mean_x(100.0f), 0.0, 0.01);
}

TEST(SurfelMap, PixelsOutsideTheRegionAreNotFused) {
  SurfelMapParams p;
  p.region_centre = {0.2f, 0.0f, 0.0f};
  p.region_radius_m = 0.1f;
  SurfelMap map(p);
  integrate(map, render(looking_down(0, 0, 1.0), {}), 0);
  EXPECT_GT(map.size(), 8000u) << "a 10 cm disc at 1 m: pi 52.5^2 = 8659 px";
  for (const Surfel& s : map.surfels())
    ASSERT_LE((s.position - p.region_centre).norm(), p.region_radius_m + 1e-4f);
}

TEST(SurfelMap, SizesThatDoNotMatchTheIntrinsicsThrow) {
  SurfelMap map;
  const View v = render(looking_down(0, 0, 1.0), {}, 64, 48);
  PinholeIntrinsics k = v.k;
  EXPECT_NO_THROW(map.integrate(v.depth, v.colour, {1, 1, 1}, k, v.T_world_camera, 0));
  const auto message = [&](const DepthImage& d, const ImageRGB8& c, std::array<float, 3> e,
                           const PinholeIntrinsics& ki) {
    return testing::integrate_error(map, d, c, e, ki, v.T_world_camera);
  };
  EXPECT_EQ(message(DepthImage(32, 48), v.colour, {1, 1, 1}, k),
            "SurfelMap::integrate: depth is 32x48, intrinsics say 64x48");
  EXPECT_EQ(message(v.depth, ImageRGB8(64, 24), {1, 1, 1}, k),
            "SurfelMap::integrate: colour is 64x24, intrinsics say 64x48");
  EXPECT_NE(message(v.depth, v.colour, {1, 0, 1}, k).find("radiance_per_unit"), std::string::npos);
  EXPECT_NE(message(v.depth, v.colour, {1, 1, NAN}, k).find("radiance_per_unit"),
            std::string::npos);
  k.fx = 0;
  EXPECT_NE(message(v.depth, v.colour, {1, 1, 1}, k).find("focal"), std::string::npos);
  SurfelMapParams bad;
  bad.max_surfels = 0;
  EXPECT_THROW(SurfelMap{bad}, std::invalid_argument);
  bad = {};
  bad.black_level = 300;
  EXPECT_THROW(SurfelMap{bad}, std::invalid_argument);
  bad = {};
  bad.index_scale = 0;
  EXPECT_THROW(SurfelMap{bad}, std::invalid_argument);
}

// The reference's cost on a VGA frame of floor and box, every pixel in the region, in the
// steady state (every pixel fuses): run with --gtest_also_run_disabled_tests.
TEST(SurfelMap, DISABLED_CostVga) {
  SurfelMap map(everywhere());
  const View v = render(looking_down(0, 0, 1.0), kBox);
  std::vector<double> ms;
  for (int frame = 0; frame < 30; ++frame) {
    const auto t0 = std::chrono::steady_clock::now();
    integrate(map, v, frame);
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  const double first = ms.front();
  std::sort(ms.begin() + 1, ms.end());
  std::printf("surfel map reference, 640x480, %zu surfels: first frame %.1f ms, then p50 %.1f ms\n",
              map.size(), first, ms[1 + (ms.size() - 1) / 2]);
}

}  // namespace
}  // namespace probeless::fusion
