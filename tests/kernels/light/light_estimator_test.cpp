#include "kernels/light/light_estimator.hpp"

#include <gtest/gtest.h>

#include <chrono>

#include "drivers/bracket/bracket_sequencer.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "support/cl_context.hpp"

namespace probeless::light {
namespace {

using probeless::testing::cl_context;

void expect_same(const envmap::ImageRGBAF& a, const envmap::ImageRGBAF& b) {
  ASSERT_EQ(a.elements().size(), b.elements().size());
  for (std::size_t i = 0; i < a.elements().size(); ++i)
    ASSERT_EQ(a.elements()[i], b.elements()[i]) << "element " << i;
}

void expect_same(const ShRgb& a, const ShRgb& b) {
  for (std::size_t i = 0; i < a.c.size(); ++i) ASSERT_EQ(a.c[i], b.c[i]) << "coefficient " << i;
}

// The service fills (push-pull) and projects the SH only when a snapshot reads them
// (fill_every_frame = false): what it reads must be what filling after every frame gave, over
// a bracketed orbit that starts new keyframes (each seeded from a filled neighbour).
TEST(LightEstimator, FillingWhenReadGivesWhatFillingEveryFrameGives) {
  auto& ctx = cl_context();
  Rig rig = sim::make_sim_rig(
      sim::parse_sim_options("realtime=0,fisheye_size=256,trajectory=orbit,threads=1"));
  LightEstimatorConfig every;
  every.keyframes.face_size = 32;
  every.keyframes.new_keyframe_distance_m = 0.03;  // several keyframes in 60 frames
  every.time_stages = false;
  LightEstimatorConfig when_read = every;
  when_read.fill_every_frame = false;
  LightEstimator a(ctx, *rig.calibration.fisheye, rig.calibration.T_rig_fisheye, every);
  LightEstimator b(ctx, *rig.calibration.fisheye, rig.calibration.T_rig_fisheye, when_read);

  BracketSequencer sequencer;
  FisheyeFrame frame;
  for (int i = 0; i < 60; ++i) {
    rig.fisheye->set_next_exposure(sequencer.next());
    ASSERT_EQ(rig.fisheye->read(frame, std::chrono::seconds(5)), ReadResult::Frame);
    ASSERT_TRUE(frame.truth && frame.truth->rig_pose);
    a.process(frame, *frame.truth->rig_pose);
    b.process(frame, *frame.truth->rig_pose);
    if (i % 7 == 6) expect_same(b.sh_of_active(), a.sh());  // a snapshot now and then
  }
  ASSERT_GE(a.keyframes().keyframes().size(), 3U);
  ASSERT_EQ(a.keyframes().keyframes().size(), b.keyframes().keyframes().size());
  for (std::size_t k = 0; k < a.keyframes().keyframes().size(); ++k)
    expect_same(b.download(*b.keyframes().keyframes()[k]),
                a.download(*a.keyframes().keyframes()[k]));
  expect_same(b.sh_of_active(), a.sh());
}

}  // namespace
}  // namespace probeless::light
