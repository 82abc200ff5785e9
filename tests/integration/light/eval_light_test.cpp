// The light estimator end to end on the synthetic rig (docs/light-capture.md "eval light").
#include <gtest/gtest.h>

#include "lab/eval/light_eval.hpp"
#include "tests/support/test_data.hpp"

namespace probeless::light {
namespace {

// A static rig: the keyframe is captured from one place, so against the room rendered from
// there the only errors are the capture's own (noise, bilinear sampling, texel averaging);
// against the truth at the object, 1.7 m away, parallax dominates when the keyframe is taken
// as distant light.
TEST(EvalLight, StaticRigCapturesTheRoomFromItsPosition) {
  LightEvalOptions o;
  o.seconds = 0.5;
  o.room_box = false;
  o.sim_spec = "trajectory=static,fisheye_size=384";
  const LightEvalReport r = evaluate_light_sim(o);
  EXPECT_EQ(r.frames, 15);
  EXPECT_EQ(r.keyframes, 1);
  ASSERT_TRUE(r.at_keyframe.all.relative_rmse.has_value());
  EXPECT_LT(*r.at_keyframe.all.relative_rmse, 0.08);
  EXPECT_GT(r.at_keyframe.all.observed, 6 * 32 * 32 / 3);  // the upper hemisphere and more
  // The floor is never seen by the upward fisheye.
  EXPECT_EQ(r.at_keyframe.faces[5].observed, 0);
  ASSERT_TRUE(r.at_probe.all.relative_rmse.has_value());
  EXPECT_GT(*r.at_probe.all.relative_rmse, *r.at_keyframe.all.relative_rmse);
  EXPECT_NEAR(r.keyframe_distance_m, 1.77, 0.05);
}

// Issue #5's bar on the slow orbit: with the room box the keyframe holds what its own position
// sees, and reprojected to the object it is within 10 % of the truth there (relative RMSE
// over observed texels); as distant light it is off by more than 100 %.
TEST(EvalLight, RoomBoxParallaxOnTheOrbit) {
  LightEvalOptions o;
  o.seconds = 1.0;
  o.sim_spec = "fisheye_size=256";
  const LightEvalReport r = evaluate_light_sim(o);
  EXPECT_TRUE(r.room_box);
  ASSERT_TRUE(r.at_probe.all.relative_rmse.has_value());
  ASSERT_TRUE(r.at_keyframe.all.relative_rmse.has_value());
  ASSERT_TRUE(r.at_probe_unreprojected.all.relative_rmse.has_value());
  EXPECT_LT(*r.at_probe.all.relative_rmse, 0.10);
  EXPECT_LT(*r.at_keyframe.all.relative_rmse, 0.06);
  EXPECT_GT(*r.at_probe_unreprojected.all.relative_rmse, 1.0);
  // The object sees less of the room from the keyframe's observations than the keyframe
  // itself (the walls below the keyframe's horizon), but most of the upper hemisphere.
  EXPECT_GT(r.at_probe.all.observed, 6 * 32 * 32 / 3);
  EXPECT_LT(r.at_probe.all.observed, r.at_keyframe.all.observed);

  o.room_box = false;  // the same run as distant light
  const LightEvalReport d = evaluate_light_sim(o);
  ASSERT_TRUE(d.at_keyframe.all.relative_rmse.has_value());
  EXPECT_GT(*d.at_keyframe.all.relative_rmse, 3 * *r.at_keyframe.all.relative_rmse);
}

TEST(EvalLight, BestScoreRuleOnTheOrbit) {
  LightEvalOptions o;
  o.seconds = 0.4;
  o.sim_spec = "fisheye_size=256";
  o.estimator.update.rule = envmap::UpdateRule::BestScore;
  const LightEvalReport r = evaluate_light_sim(o);
  ASSERT_TRUE(r.at_last_capture.all.relative_rmse.has_value());
  EXPECT_LT(*r.at_last_capture.all.relative_rmse, 0.15);
  EXPECT_EQ(r.rule, "best_score");
}

// Issue #18: a rig calibrated with OCamCalib captures light. The shared OCamCalib file drives
// the sim's fisheye (rendered and calibrated through that model), against the same lens as a
// Kannala-Brandt model fitted to it: the update kernel sees both through its table, so the
// errors agree within 10 % (measured: 0.0170 vs 0.0169 at the object over 2 s at 1024 x 768).
TEST(EvalLight, OCamCalibRigCapturesLikeKannalaBrandt) {
  PROBELESS_REQUIRE_DATA("fisheye/ocamcalib/calib_results_fisheye.txt");
  const std::string file =
      (::probeless::testing::shared_data_dir() / "fisheye/ocamcalib/calib_results_fisheye.txt")
          .string();
  LightEvalOptions o;
  o.seconds = 1.0;
  o.sim_spec = "fisheye_ocam=" + file;
  const LightEvalReport ocam = evaluate_light_sim(o);
  o.sim_spec += ",fisheye_ocam_model=kannala_brandt";
  const LightEvalReport kb = evaluate_light_sim(o);
  for (const LightEvalReport* r : {&ocam, &kb}) {
    ASSERT_TRUE(r->at_probe.all.relative_rmse.has_value());
    ASSERT_TRUE(r->at_keyframe.all.relative_rmse.has_value());
    // This lens sees about 65 degrees off its axis: a cone of the ceiling, not the hemisphere.
    EXPECT_GT(r->at_keyframe.all.observed, 6 * 32 * 32 / 6);
  }
  EXPECT_NEAR(ocam.at_probe.all.observed, kb.at_probe.all.observed,
              0.02 * kb.at_probe.all.observed);
  EXPECT_NEAR(*ocam.at_probe.all.relative_rmse, *kb.at_probe.all.relative_rmse,
              0.1 * *kb.at_probe.all.relative_rmse);
  EXPECT_NEAR(*ocam.at_keyframe.all.relative_rmse, *kb.at_keyframe.all.relative_rmse,
              0.1 * *kb.at_keyframe.all.relative_rmse);
  EXPECT_LT(*ocam.at_probe.all.relative_rmse, 0.10);
}

}  // namespace
}  // namespace probeless::light
