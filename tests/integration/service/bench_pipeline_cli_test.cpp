// `probeless bench pipeline` as a user runs it: the numbers come out (not their size: timing
// is for the bench, not for tests), and --prerender reaches the sim and carries the light load.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless::testing {
namespace {

using namespace std::chrono_literals;

std::string probeless_binary() {
  const char* b = std::getenv("PROBELESS_BINARY");
  return b ? b : "probeless";
}

TEST(BenchPipelineCli, PrerenderRunsThePipelineOnFramesRenderedBeforehand) {
  const auto json = scratch_dir() / "bench-pipeline.json";
  Subprocess bench({probeless_binary(), "bench", "pipeline", "--frames", "6", "--warmup", "2",
                    "--prerender", "--json", json.string()},
                   {}, true);
  ASSERT_EQ(bench.wait(120s).value_or(-1), 0) << bench.output();
  std::ifstream f(json);
  const nlohmann::json j = nlohmann::json::parse(f);
  // "frames" counts the frames out after the moment the bench's main thread saw the warm-up
  // end (it polls) until the last one was encoded (it waits 200 ms for it): on a busy machine
  // the window starts a frame or more late, so 5 of 6 is no fault. The pipeline itself is
  // lossless; what does not depend on the machine's speed is the bound.
  const int frames = j["frames"].get<int>();
  EXPECT_GE(frames, 0) << bench.output();
  EXPECT_LE(frames, 6) << bench.output();
  EXPECT_GE(j["fps"].get<double>(), 0);
  if (frames > 0) {
    EXPECT_GT(j["fps"].get<double>(), 0);
  }
  // Warm-up + timed + the 10 frames after them that keep the timed ones in the steady state.
  EXPECT_NE(j["source"].get<std::string>().find("prerender=18"), std::string::npos) << j["source"];
  // Where the CPU went, by thread: the processing thread at least, in ms per frame.
  ASSERT_TRUE(j.contains("cpu_ms_per_frame_by_thread")) << j.dump();
  if (frames > 0) {
    EXPECT_GT(j["cpu_ms_per_frame_by_thread"].value("process", 0.0), 0.0) << j.dump();
  }
  // How many fisheye frames the light thread got through in the run is wall time against its
  // speed (the fisheye runs at 50 frames/s of wall time): reported, not asserted.
  EXPECT_GE(j["light_frames"].get<int>(), 0) << bench.output();
  EXPECT_TRUE(j["stages"].contains("render"));
}

TEST(BenchPipelineCli, PrerenderOfARecordingIsAClearError) {
  Subprocess bench({probeless_binary(), "bench", "pipeline", "--frames", "6", "--prerender",
                    "--source", "replay:/nowhere"},
                   {}, true);
  EXPECT_TRUE(bench.wait_for_line("--prerender needs a sim source", 60s).has_value())
      << bench.output();
  EXPECT_EQ(bench.wait(60s).value_or(-1), 1);
}

}  // namespace
}  // namespace probeless::testing
