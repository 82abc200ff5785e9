// `probeless bench latency` briefly, as a user runs it: against a real `probeless run` on the
// stamping sim, the MJPEG, RTSP and WebRTC (WHEP) clients decode frames whose stamp reads
// back after the compositor, JPEG q80 and H.264 at 2 Mbit/s, with a latency that is plausible
// (not a timing bar: the bench reports the numbers). Without GStreamer's WebRTC plugins,
// WebRTC is reported as skipped, with the reason.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string_view>

#include "app/outputs/webrtc_output.hpp"
#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless::testing {
namespace {

using namespace std::chrono_literals;

TEST(BenchLatencyCli, EveryPathDecodesStampsWithAPlausibleLatency) {
  const bool webrtc = webrtc_missing_plugins().empty();
  const auto json = scratch_dir() / "bench-latency.json";
  Subprocess bench({probeless_binary(), "bench", "latency", "--seconds", "2", "--warmup", "0.5",
                    "--json", json.string()},
                   {}, true);
  ASSERT_EQ(bench.wait(300s).value_or(-1), 0) << bench.output();
  std::ifstream f(json);
  const nlohmann::json j = nlohmann::json::parse(f);
  for (const char* path : {"mjpeg", "rtsp", "webrtc"}) {
    SCOPED_TRACE(path);
    if (std::string_view(path) == "webrtc" && !webrtc) continue;
    ASSERT_TRUE(j.contains(path)) << j.dump(2);
    const nlohmann::json& p = j[path];
    ASSERT_TRUE(p.contains("p50_ms")) << p.dump(2);
    const int frames = p["frames"].get<int>(), timed = p["timed"].get<int>();
    // A few frames: the live sim leaves the service 8-10 fps on a shared 2-core host.
    EXPECT_GE(timed, 3) << p.dump(2);
    // The stamp survives the compositor and the codec: nearly every frame reads.
    EXPECT_GE(timed, frames * 9 / 10) << p.dump(2);
    EXPECT_GT(p["min_ms"].get<double>(), 0) << p.dump(2);
    EXPECT_GT(p["p50_ms"].get<double>(), 0);
    EXPECT_LT(p["p99_ms"].get<double>(), 2000);
  }
  EXPECT_TRUE(j["mjpeg"].contains("service")) << "the MJPEG parts carried no send time";
  ASSERT_TRUE(j.contains("webrtc"));
  if (!webrtc) {
    EXPECT_TRUE(j["webrtc"].contains("skipped")) << j["webrtc"].dump();
  }
}

}  // namespace
}  // namespace probeless::testing
