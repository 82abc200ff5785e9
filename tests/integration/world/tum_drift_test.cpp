// `probeless run --source tum:../shared/data/rgbd/tum_fr1_rpy` keeps a virtual object on the
// same real spot (issue #17's bar): the service's pipeline on the real Kinect sequence, a
// sphere placed where the first frame's optical axis meets the scene, and per frame the pixel
// distance between where it is drawn (its silhouette's centroid in the rendered layer) and
// where the motion-capture pose says it belongs. With `method = "truth"` that is the
// plumbing alone (~0 px); with `method = "dense"` it is the tracker.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <vector>

#include "app/pipeline/pipeline.hpp"
#include "drivers/rig_factory.hpp"
#include "kernels/tracking/dense_tracker.hpp"
#include "support/pipeline_frames.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

constexpr double kSphereRadius = 0.05;  // the built-in sphere (0.1 m) at scale 0.5
constexpr int kFrames = 150;

struct Drift {
  std::vector<double> px;  // per frame where the object is inside the picture
  double truth_turn_deg = 0;
  double p50() { return quantile(0.5); }
  double p95() { return quantile(0.95); }
  double quantile(double q) {
    std::sort(px.begin(), px.end());
    return px.empty() ? 0 : px[static_cast<std::size_t>(q * (px.size() - 1))];
  }
};

Drift drift_over_run(const std::string& spec, const std::string& method) {
  // Where the object stands: on the first frame's optical axis at the median depth of its
  // central 64x64 window (the registration point of `eval tracking`), in the trajectory's
  // world, which `[world] anchor = "rig"` takes from the first frame's pose.
  Rig probe = open_rig(spec);
  RgbdFrame first;
  if (probe.rgbd->read(first, 5s) != ReadResult::Frame || !first.truth || !first.truth->rig_pose)
    throw std::runtime_error("tum: no first frame with a pose");
  std::vector<std::uint16_t> centre;
  const PinholeIntrinsics k = probe.calibration.rgb.intrinsics();
  for (int y = k.height / 2 - 32; y < k.height / 2 + 32; ++y)
    for (int x = k.width / 2 - 32; x < k.width / 2 + 32; ++x)
      if (first.depth.at(x, y) > 0) centre.push_back(first.depth.at(x, y));
  std::nth_element(centre.begin(), centre.begin() + centre.size() / 2, centre.end());
  const Pose T_world_camera0 = *first.truth->rig_pose * probe.calibration.T_rig_rgb;
  const Eigen::Vector3d base =
      T_world_camera0 * Eigen::Vector3d(0, 0, centre[centre.size() / 2] * 1e-3);
  const Eigen::Vector3d sphere_centre = base + Eigen::Vector3d(0, 0, kSphereRadius);

  ServiceConfig config;
  config.source = spec;
  config.tracking.method = method;
  config.tracking.rolling_shutter_readout_s = 0.028;  // a Kinect v1 (docs/configuration.md)
  config.max_frames = kFrames;
  config.ground.enabled = false;
  ObjectConfig sphere;
  sphere.shape = "sphere";
  sphere.scale = 0.5;
  sphere.position = base;
  config.objects = {sphere};
  PipelineOptions options;
  options.lossless = true;
  options.keep_matte = true;
  options.serve_http = false;
  Pipeline pipeline(config, open_rig(spec), options);
  Drift drift;
  pipeline.start();
  testing::for_each_output_frame(pipeline, [&](const CompositeFrame& f) {
    if (!f.virtual_depth || !f.truth || !f.truth->rig_pose) return;
    const Pose T_world_camera = *f.truth->rig_pose * probe.calibration.T_rig_rgb;
    drift.truth_turn_deg =
        std::max(drift.truth_turn_deg,
                 T_world_camera.rotation.angularDistance(T_world_camera0.rotation) * 180 / M_PI);
    const Eigen::Vector3d c = T_world_camera.inverse() * sphere_centre;
    const double u = k.fx * c.x() / c.z() + k.cx, v = k.fy * c.y() / c.z() + k.cy;
    const double margin = 1.5 * k.fx * kSphereRadius / c.z();  // the whole sphere in view
    if (c.z() <= 0 || u < margin || v < margin || u > k.width - margin || v > k.height - margin)
      return;
    double su = 0, sv = 0, n = 0;
    const ImageF& depth = *f.virtual_depth;
    for (int y = 0; y < depth.height(); ++y)
      for (int x = 0; x < depth.width(); ++x)
        if (depth.at(x, y) > 0) su += x, sv += y, ++n;
    // Not drawn (tracking lost) is no drift: the object is never drawn at a wrong pose.
    if (n == 0) return;
    drift.px.push_back(std::hypot(su / n - u, sv / n - v));
  });
  pipeline.stop();
  if (pipeline.fatal_error()) throw std::runtime_error(*pipeline.fatal_error());
  return drift;
}

const std::string kSequence = "rgbd/tum_fr1_rpy";

TEST(TumDrift, TruthPosesKeepTheObjectOnItsSpot) {
  PROBELESS_REQUIRE_DATA(kSequence);
  Drift d = drift_over_run(
      "tum:" + (testing::shared_data_dir() / kSequence).string() + "?realtime=0", "truth");
  std::cout << "tum_fr1_rpy, method truth: " << d.px.size() << " frames, drift p50 " << d.p50()
            << " px, p95 " << d.p95() << " px (truth turns " << d.truth_turn_deg << " deg)\n";
  // The first 5 s of fr1/rpy turn the camera up to ~100 degrees: the object is in view in
  // about a third of them.
  ASSERT_GE(d.px.size(), 40u);
  // A silhouette's centroid is not quite its centre's projection (perspective): < 1 px here.
  EXPECT_LT(d.p95(), 1.0);
}

// The bar is the registration bar of `eval tracking` on this sequence (reg_px_p95
// half the best OpenCV odometry's, 7.5 px): not met yet. The service measures p95 ~20 px here
// (docs/tracking.md "Remaining gap": frames 76-83, after the longest, blurred excursion, carry
// 1-2 degrees); the bound guards that figure against regressions until the gap is closed.
TEST(TumDrift, DenseTrackingKeepsTheObjectOnItsSpot) {
  PROBELESS_REQUIRE_DATA(kSequence);
  Drift d = drift_over_run(
      "tum:" + (testing::shared_data_dir() / kSequence).string() + "?realtime=0", "dense");
  std::cout << "tum_fr1_rpy, method dense: " << d.px.size() << " frames, drift p50 " << d.p50()
            << " px, p95 " << d.p95() << " px (truth turns " << d.truth_turn_deg << " deg)\n";
  ASSERT_GE(d.px.size(), 40u) << "the object must be drawn while it is in view";
  EXPECT_LT(d.p95(), 26.0);
}

}  // namespace
}  // namespace probeless
