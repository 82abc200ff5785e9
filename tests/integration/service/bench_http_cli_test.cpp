// `probeless bench http` at small counts, as a user runs it: against a real `probeless run`
// over loopback, a new viewer gets its first frame under the abuse, the viewers that leave
// with a reset were served first, and the service's descriptors are back at their baseline.
// The frame rates and times are the bench's to report, not the test's to assert.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless::testing {
namespace {

using namespace std::chrono_literals;

TEST(BenchHttpCli, AbuseLeavesTheServiceServingAndItsDescriptorsAtBaseline) {
  const auto json = scratch_dir() / "bench-http.json";
  Subprocess bench({probeless_binary(), "bench", "http", "--viewers", "4", "--stalled", "2",
                    "--idle", "20", "--slowloris", "20", "--leaving", "200", "--seconds", "1",
                    "--settle-s", "0", "--json", json.string()},
                   {}, true);
  ASSERT_EQ(bench.wait(300s).value_or(-1), 0) << bench.output();
  std::ifstream f(json);
  const nlohmann::json j = nlohmann::json::parse(f);
  for (const char* key : {"fps_alone", "fps_loaded", "ratio", "fds_before", "fds_after",
                          "rss_before_mb", "rss_after_mb", "new_viewer_ms"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_GT(j["new_viewer_ms"].get<double>(), 0) << "a new viewer got no frame under the load";
  EXPECT_EQ(j["details"]["new_viewers_without_a_frame"].get<int>(), 0);
  EXPECT_EQ(j["details"]["leaving"]["got_bytes"].get<int>(), 200)
      << "viewers were refused before leaving";
  EXPECT_LE(j["fds_after"].get<int>(), j["fds_before"].get<int>()) << bench.output();
  EXPECT_GT(j["details"]["load"]["viewer_bytes"].get<double>(), 0);
  EXPECT_GT(j["rss_after_mb"].get<double>(), 0);
}

}  // namespace
}  // namespace probeless::testing
