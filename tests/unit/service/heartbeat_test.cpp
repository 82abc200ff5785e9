#include "app/service/heartbeat.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace probeless {
namespace {

using namespace std::chrono_literals;

TEST(Heartbeats, SilentHeartbeatBecomesStaleAndBeatingMakesItFresh) {
  HeartbeatRegistry registry(30ms);
  Heartbeat a = registry.add("a");
  Heartbeat b = registry.add("b");
  EXPECT_TRUE(registry.stale().empty());
  std::this_thread::sleep_for(60ms);
  b.beat();
  EXPECT_EQ(registry.stale(), std::vector<std::string>{"a"});
  const nlohmann::json j = registry.to_json();
  EXPECT_EQ(j["stale"], nlohmann::json::array({"a"}));
  EXPECT_GE(j["threads"]["a"]["age_ms"].get<int>(), 30);
  EXPECT_EQ(j["stale_after_ms"], 30);
  a.beat();
  EXPECT_TRUE(registry.stale().empty());
}

TEST(Heartbeats, AThreadThatEndsIsNoLongerWatched) {
  HeartbeatRegistry registry(10ms);
  {
    Heartbeat gone = registry.add("gone");
    Heartbeat moved = std::move(gone);  // the move keeps one registration
    EXPECT_EQ(registry.to_json()["threads"].size(), 1u);
  }
  std::this_thread::sleep_for(20ms);
  EXPECT_TRUE(registry.stale().empty());
  EXPECT_TRUE(registry.to_json()["threads"].empty());
  Heartbeat none;  // not registered: beating it does nothing
  none.beat();
  EXPECT_FALSE(none);
}

TEST(Heartbeats, WedgedHeartbeatBlocksItsThreadUntilReleased) {
  HeartbeatRegistry registry(1000ms);
  registry.wedge_after("light", 3);
  std::atomic<int> beats{0};
  std::thread light([&] {
    Heartbeat h = registry.add("light");
    for (int i = 0; i < 5; ++i) {
      h.beat();
      ++beats;
    }
  });
  Heartbeat other = registry.add("output");
  for (int i = 0; i < 10; ++i) other.beat();  // only the named heartbeat wedges
  const auto until = std::chrono::steady_clock::now() + 10s;
  while (beats < 2 && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(1ms);
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(beats.load(), 2) << "the third beat must block";
  registry.release_wedged();
  light.join();
  EXPECT_EQ(beats.load(), 5);
}

}  // namespace
}  // namespace probeless
