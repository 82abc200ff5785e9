#include "kernels/hdr/colour_exposure.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/camera/kannala_brandt.hpp"
#include "drivers/sim/sim_rig.hpp"

namespace probeless {
namespace {

// A synthetic pair with a known colour gain per channel. The radiance of a point is a smooth
// function g of its direction from the fisheye, so the fisheye image (g of each pixel's ray)
// and the colour image (gamma(k_c g) of each pixel's point) agree for any depth: then
// e_c = s / k_c, s the fisheye's radiance scale.
struct Pair {
  PinholeCamera rgb{PinholeIntrinsics{160, 120, 100.0, 100.0, 79.5, 59.5}};
  std::shared_ptr<const CameraModel> fisheye =
      std::make_shared<KannalaBrandtCamera>(KannalaBrandtCamera::equidistant(256, 180.0));
  Pose T_rig_rgb;      // the rig is the colour camera: x right, y down, z forward
  Pose T_rig_fisheye;  // 5 cm above it, looking up (rig -y), its y along rig +z
  RgbdFrame rgbd;
  FisheyeFrame raw;

  Pair() {
    Eigen::Matrix3d r;
    r << Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitY();
    T_rig_fisheye.rotation = Eigen::Quaterniond(r);
    T_rig_fisheye.translation = Eigen::Vector3d(0.0, -0.05, 0.0);
  }
};

Eigen::Vector3d g(const Eigen::Vector3d& d) {  // d: unit direction in the fisheye frame
  Eigen::Vector3d v(0.3 + 0.2 * d.x(), 0.4 + 0.1 * d.y(), 0.2 + 0.15 * d.z());
  if (d.x() > 0.4 && d.z() > 0.3) v *= 4.0;  // a bright patch the colour camera clips
  return v;
}

constexpr double kFisheyeScale = 50.0;  // converted fisheye radiance = 50 g

// Colour gains k, wall at `depth_mm` (0 = no depth anywhere).
Pair make_pair(const Eigen::Vector3d& k, std::uint16_t depth_mm) {
  Pair p;
  const int bits = 12;
  const std::uint16_t black = 256;
  const int range = 4095 - black;
  p.raw.bit_depth = bits;
  p.raw.black_level = black;
  p.raw.exposure.exposure = Exposure{0.01, 0.0};
  p.raw.raw = ImageRGB16(256, 256, 0);
  const double dn_per_unit = kFisheyeScale * range * 0.01;  // undoes the conversion's 1/(range E)
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 256; ++x) {
      const auto ray = p.fisheye->unproject(Eigen::Vector2d(x, y));
      if (!ray) continue;
      const Eigen::Vector3d v = g(*ray) / 4.0;  // the bright patch stays below saturation
      for (int c = 0; c < 3; ++c)
        p.raw.raw.at(x, y, c) = static_cast<std::uint16_t>(
            std::lround(black + std::min(4095.0 - black, 4.0 * v[c] * dn_per_unit)));
    }
  }
  p.rgbd.colour = ImageRGB8(160, 120);
  p.rgbd.depth = DepthImage(160, 120, depth_mm);
  const Pose T_fisheye_rgb = p.T_rig_fisheye.inverse() * p.T_rig_rgb;
  for (int y = 0; y < 120; ++y) {
    for (int x = 0; x < 160; ++x) {
      const Eigen::Vector3d ray = *p.rgb.unproject(Eigen::Vector2d(x, y));
      const Eigen::Vector3d point = ray * (2.0 / ray.z());  // a wall 2 m ahead
      const Eigen::Vector3d d = (T_fisheye_rgb * point).normalized();
      for (int c = 0; c < 3; ++c) {
        const double linear = std::clamp(k[c] * g(d)[c], 0.0, 1.0);
        p.rgbd.colour.at(x, y, c) =
            static_cast<std::uint8_t>(std::lround(255.0 * std::pow(linear, 1.0 / 2.2)));
      }
    }
  }
  return p;
}

TEST(ColourExposure, RecoversAKnownGainPerChannel) {
  const Eigen::Vector3d k(1.2, 0.8, 1.9);
  Pair p = make_pair(k, 2000);
  ColourExposureEstimator est(p.rgb, p.fisheye, p.T_rig_rgb, p.T_rig_fisheye);
  ASSERT_TRUE(est.update(p.rgbd, p.raw));
  EXPECT_TRUE(est.estimate().valid);
  EXPECT_GE(est.estimate().matches, 100);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(est.estimate().e[c], kFisheyeScale / k[c], 0.02 * kFisheyeScale / k[c]) << c;
  }
}

// The bright patch clips in the colour image; counting it would bias e upward by far more
// than the tolerance (the patch is 4x brighter, its colour held at 1).
TEST(ColourExposure, SkipsSaturatedColourSamples) {
  const Eigen::Vector3d k(1.5, 1.5, 1.5);
  Pair p = make_pair(k, 2000);
  int clipped = 0;
  for (int y = 4; y < 60; y += 8) {
    for (int x = 4; x < 160; x += 8) clipped += p.rgbd.colour.at(x, y, 0) == 255;
  }
  ASSERT_GE(clipped, 10);  // the patch is in the sampled region
  ColourExposureEstimator est(p.rgb, p.fisheye, p.T_rig_rgb, p.T_rig_fisheye);
  ASSERT_TRUE(est.update(p.rgbd, p.raw));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(est.estimate().e[c], kFisheyeScale / k[c], 0.02 * kFisheyeScale / k[c]) << c;
  }
}

TEST(ColourExposure, KeepsThePreviousEstimateWithTooFewMatches) {
  const Eigen::Vector3d k(1.0, 1.0, 1.0);
  Pair good = make_pair(k, 2000);
  ColourExposureEstimator est(good.rgb, good.fisheye, good.T_rig_rgb, good.T_rig_fisheye);
  ASSERT_TRUE(est.update(good.rgbd, good.raw));
  const Eigen::Vector3d before = est.estimate().e;

  Pair no_depth = make_pair(Eigen::Vector3d(0.5, 0.5, 0.5), 0);
  EXPECT_FALSE(est.update(no_depth.rgbd, no_depth.raw));
  EXPECT_EQ(est.estimate().matches, 0);
  EXPECT_EQ(est.estimate().e, before);
  EXPECT_TRUE(est.estimate().valid);

  // The minimum is configurable: above what the frame offers, nothing changes.
  ColourExposureParams strict;
  strict.min_matches = 100000;
  ColourExposureEstimator strict_est(good.rgb, good.fisheye, good.T_rig_rgb, good.T_rig_fisheye,
                                     strict);
  EXPECT_FALSE(strict_est.update(good.rgbd, good.raw));
  EXPECT_GT(strict_est.estimate().matches, 0);
  EXPECT_FALSE(strict_est.estimate().valid);
  EXPECT_EQ(strict_est.estimate().e, Eigen::Vector3d::Ones());
}

TEST(ColourExposure, RejectsBadInput) {
  Pair p = make_pair(Eigen::Vector3d::Ones(), 2000);
  EXPECT_THROW(ColourExposureEstimator(p.rgb, nullptr, p.T_rig_rgb, p.T_rig_fisheye),
               std::invalid_argument);
  ColourExposureParams bad;
  bad.stride = 0;
  EXPECT_THROW(ColourExposureEstimator(p.rgb, p.fisheye, p.T_rig_rgb, p.T_rig_fisheye, bad),
               std::invalid_argument);
  bad = {};
  bad.colour_saturated = 2;
  EXPECT_THROW(ColourExposureEstimator(p.rgb, p.fisheye, p.T_rig_rgb, p.T_rig_fisheye, bad),
               std::invalid_argument);

  ColourExposureEstimator est(p.rgb, p.fisheye, p.T_rig_rgb, p.T_rig_fisheye);
  RgbdFrame mismatched = p.rgbd;
  mismatched.depth = DepthImage(80, 60, 2000);
  EXPECT_THROW(est.update(mismatched, p.raw), std::invalid_argument);
  RgbdFrame small = p.rgbd;
  small.colour = ImageRGB8(80, 60);
  small.depth = DepthImage(80, 60, 2000);
  EXPECT_THROW(est.update(small, p.raw), std::invalid_argument);
  FisheyeFrame wrong_size = p.raw;
  wrong_size.raw = ImageRGB16(128, 128);
  EXPECT_THROW(est.update(p.rgbd, wrong_size), std::invalid_argument);
  FisheyeFrame zero_exposure = p.raw;
  zero_exposure.exposure.exposure.time_s = 0.0;
  EXPECT_THROW(est.update(p.rgbd, zero_exposure), std::invalid_argument);
  EXPECT_FALSE(est.estimate().valid);  // nothing half-applied
}

// On the sim rig (real calibration, rendered room): enough matches, and the channel ratios
// within what its white balance can do (each channel's gain is clamped to [0.5, 2], so
// e_c / e_g lies in [1/4, 4]); a static rig gives the same estimate on two frames.
TEST(ColourExposure, WorksOnTheSimRig) {
  sim::SimOptions options;
  options.trajectory = sim::TrajectoryKind::Static;
  options.realtime = false;
  options.fisheye_size = 256;
  options.ground_truth = false;
  Rig rig = sim::make_sim_rig(options);
  const auto& cal = rig.calibration;
  ColourExposureEstimator est(cal.rgb, cal.fisheye, cal.T_rig_rgb, cal.T_rig_fisheye);
  Eigen::Vector3d first = Eigen::Vector3d::Ones();
  for (int frame = 0; frame < 12; ++frame) {
    RgbdFrame rgbd;
    FisheyeFrame fisheye;
    ASSERT_EQ(rig.rgbd->read(rgbd, std::chrono::milliseconds(5000)), ReadResult::Frame);
    ASSERT_EQ(rig.fisheye->read(fisheye, std::chrono::milliseconds(5000)), ReadResult::Frame);
    if (frame != 0 && frame != 11) continue;  // the sim's auto-exposure settles in between
    ASSERT_TRUE(est.update(rgbd, fisheye)) << "matches " << est.estimate().matches;
    const Eigen::Vector3d e = est.estimate().e;
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(e[c], 0.0);
      EXPECT_GE(e[c] / e[1], 0.25) << c;
      EXPECT_LE(e[c] / e[1], 4.0) << c;
    }
    if (frame == 0) first = e;
  }
  EXPECT_LT((est.estimate().e.array() / first.array() - 1.0).abs().maxCoeff(), 0.5);
}

}  // namespace
}  // namespace probeless
