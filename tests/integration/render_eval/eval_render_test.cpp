// `probeless eval render` end to end on the sim (docs/rendering.md "eval render").
#include <gtest/gtest.h>

#include "lab/eval/render_eval.hpp"

namespace probeless::eval {
namespace {

// Issue #6's bars on the sim, as `probeless eval render` measures them (the run is
// deterministic: the same numbers under load). After the sim's lamp switch the diffuse objects
// lit by the captured light are within 10 % of the truth within 0.5 s, and match before it.
// The chrome sphere, after the 2 s of orbit, within 10 % relative RMSE of the truth:
// 0.095 with 192 px faces and Catmull-Rom reprojection (0.122 at 128, 0.24 before L exposed
// the window's clouds unclipped; docs/light-capture.md). Its lower half is held to the colour
// camera's fill (0.25; 0.53 without it), objects (0.096) and shadow (0.002; 0.06 with the
// clouds clipped) near what they measure, so a regression shows.
TEST(EvalRender, ObjectsFollowTheLampSwitch) {
  RenderEvalOptions o;
  o.orbit_s = 2.0;
  o.after_switch_s = 1.0;
  const RenderEvalReport r = evaluate_render_sim(o);
  EXPECT_EQ(r.fisheye_frames, 90);
  EXPECT_GE(r.snapshots, 8);  // 4 Hz
  EXPECT_LT(r.compare_t_s, r.switch_t_s);
  ASSERT_TRUE(r.lamp_response_s.has_value());
  EXPECT_LE(*r.lamp_response_s, 0.5);
  EXPECT_LT(r.lamp_rel_error_before, 0.10);
  EXPECT_LT(r.lamp_rel_error_final, 0.10);
  EXPECT_LT(r.truth_drop, 0.9)
      << "the switch must be visible in the truth for the test to mean much";
  EXPECT_GT(r.object_pixels, 1000);
  EXPECT_GT(r.shadow_pixels, 500);
  EXPECT_LT(r.shadow_mean_truth, 0) << "a shadow darkens";
  EXPECT_LT(r.shadow_rel_error, 0.01);
  EXPECT_LT(r.object_rel_error, 0.15);
  EXPECT_GT(r.sphere_pixels, 30000);
  EXPECT_LT(r.sphere_rel_rmse, 0.10) << "issue #6's chrome-sphere bar";
  EXPECT_LT(r.sphere_rel_rmse_lower, 0.30) << "the table below the horizon";
}

TEST(EvalRender, RejectsWhatItCannotCompare) {
  RenderEvalOptions o;
  o.config.source = "replay:/nowhere";
  EXPECT_THROW(evaluate_render_sim(o), std::invalid_argument);
  o = {};
  o.orbit_s = 7;  // the switch is at 6 s of world time
  EXPECT_THROW(evaluate_render_sim(o), std::invalid_argument);
  o = {};
  o.config.objects.clear();
  EXPECT_THROW(evaluate_render_sim(o), std::invalid_argument);
  o = {};
  o.after_switch_s = 0;
  EXPECT_THROW(evaluate_render_sim(o), std::invalid_argument);
}

TEST(EvalRender, RelativeErrorOverAMask) {
  render::ImageRGBAF a(2, 1), b(2, 1);
  for (int c = 0; c < 3; ++c) {
    a.at(0, 0, c) = 1.1f;
    b.at(0, 0, c) = 1.0f;
    a.at(1, 0, c) = 50.f;  // outside the mask
  }
  EXPECT_NEAR(relative_rgb_error(a, b, {true, false}), 0.1, 1e-6);
  EXPECT_EQ(relative_rgb_error(a, b, {false, false}), 0.0);
  EXPECT_THROW(relative_rgb_error(a, b, {true}), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::eval
