// The service with `[world] anchor = "marker"` on the sim's board: no object until the board
// is seen, then the objects stand on it (where the board truly is, seen with the sim's truth),
// and /status says the anchor was found.
#include <gtest/gtest.h>

#include "app/pipeline/pipeline.hpp"
#include "drivers/rig_factory.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "support/pipeline_frames.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

TEST(MarkerService, ObjectsStandOnTheBoardOnceItIsSeen) {
  ServiceConfig config;
  config.source = "sim:realtime=0,trajectory=tabletop,board=1";
  config.tracking.method = "truth";
  config.world.anchor = "marker";
  config.world.marker = sim::board_spec();
  config.max_frames = 15;
  // The frame count is exact: a slow sim frame on a busy machine must not become a NO SIGNAL
  // repeat of the last one (measured: 279-315 ms for one tabletop frame under load 5).
  config.no_signal_after_ms = 60'000;
  ObjectConfig box;  // one small box on the board's centre
  box.shape = "box";
  box.scale = 0.5;
  config.objects = {box};
  PipelineOptions options;
  options.lossless = true;
  options.keep_matte = true;
  options.serve_http = false;
  Rig rig = open_rig(config.source);
  const PinholeIntrinsics k = rig.calibration.rgb.intrinsics();
  const Pose T_rig_rgb = rig.calibration.T_rig_rgb;
  Pipeline pipeline(config, std::move(rig), options);
  pipeline.start();
  int drawn = 0, frames = 0;
  bool drawn_before = false;
  testing::for_each_output_frame(pipeline, [&](const CompositeFrame& f) {
    ++frames;
    ASSERT_TRUE(f.virtual_depth && f.truth && f.truth->rig_pose);
    // The board's centre, where the box stands, projected with the truth.
    const Pose T_world_camera = *f.truth->rig_pose * T_rig_rgb;
    const Eigen::Vector3d c = T_world_camera.inverse() * sim::board_world_pose().translation;
    const int u = static_cast<int>(k.fx * c.x() / c.z() + k.cx);
    const int v = static_cast<int>(k.fy * c.y() / c.z() + k.cy);
    int object_px = 0, near_centre = 0;
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x)
        if (f.virtual_depth->at(x, y) > 0) {
          ++object_px;
          near_centre += std::abs(x - u) < 40 && std::abs(y - v) < 40;
        }
    if (object_px == 0) {
      EXPECT_EQ(drawn, 0) << "once anchored, the box stays while the board is in view";
      return;
    }
    ++drawn;
    drawn_before = true;
    // The box's foot is at the board's centre: most of the box is within 40 px of it.
    EXPECT_GT(near_centre, object_px / 2)
        << "frame " << f.sequence << " at (" << u << ", " << v << ")";
  });
  const auto status = pipeline.status();
  pipeline.stop();
  EXPECT_FALSE(pipeline.fatal_error().has_value()) << pipeline.fatal_error().value_or("");
  EXPECT_EQ(frames, 15);
  EXPECT_TRUE(drawn_before);
  EXPECT_GE(drawn, 12) << "the detector's answer comes a frame or two late, then every frame";
  EXPECT_EQ(status["tracking"]["anchor"]["kind"], "marker");
  EXPECT_EQ(status["tracking"]["anchor"]["found"], true) << status["tracking"].dump();
}

}  // namespace
}  // namespace probeless
