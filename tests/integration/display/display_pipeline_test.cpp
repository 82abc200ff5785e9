// The tethered display as the pipeline attaches it ([display] enabled): a screen that cannot
// be opened is reported in /status and retried, and never stops or fails the service.
#include <gtest/gtest.h>

#include "app/pipeline/pipeline.hpp"
#include "drivers/rig_factory.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

TEST(DisplayPipeline, AMissingScreenIsInStatusAndTheServiceRunsOn) {
  ServiceConfig config;
  config.source = "sim:realtime=0,trajectory=static";
  config.max_frames = 10;
  config.display.enabled = true;
  config.display.screen.card = "/nonexistent/card0";  // the same answer on a machine with a GPU
  PipelineOptions options;
  options.serve_http = false;
  Pipeline pipeline(config, open_rig(config.source), options);
  pipeline.start();
  ASSERT_TRUE(pipeline.wait_finished(120s));
  const auto status = pipeline.status();
  pipeline.stop();
  EXPECT_FALSE(pipeline.fatal_error().has_value()) << pipeline.fatal_error().value_or("");
  EXPECT_EQ(pipeline.frames_processed(), 10u);
  ASSERT_TRUE(status.contains("display")) << status.dump();
  const auto& d = status["display"];
  EXPECT_EQ(d["state"], "error") << d.dump();
  EXPECT_EQ(d["last_error"], "no DRM device /nonexistent/card0 (no KMS driver bound to it)");
  EXPECT_EQ(d["flips"], 0);
  EXPECT_GT(d["frames_in"].get<int>(), 0) << "the output loop does not feed the display";
  // Without [display] the status has no display entry.
  config.display.enabled = false;
  Pipeline plain(config, open_rig(config.source), options);
  EXPECT_FALSE(plain.status().contains("display"));
}

}  // namespace
}  // namespace probeless
