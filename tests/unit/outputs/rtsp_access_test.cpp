// Who may watch the RTSP stream (issue #20 item 4): basic authentication and a session cap,
// met by a raw RTSP client over loopback and by a real player.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include "app/outputs/rtsp_server.hpp"
#include "http_test_client.hpp"
#include "rtsp_test_client.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

RtspServerConfig ephemeral() {
  RtspServerConfig config;
  config.port = 0;
  config.path = "/test";
  return config;
}

// Frames at 30 Hz while it lives: a DESCRIBE waits for the live media to preroll.
class Feeder {
 public:
  explicit Feeder(RtspServer& server)
      : thread_([&server](std::stop_token stop) {
          const auto frame = std::make_shared<const ImageRGB8>(320, 240);
          while (!stop.stop_requested()) {
            server.push(frame, monotonic_now_ns());
            std::this_thread::sleep_for(33ms);
          }
        }) {}

 private:
  std::jthread thread_;
};

// One DESCRIBE on a fresh connection; the status line and headers of the answer.
std::string describe(const RtspServer& server, const std::string& extra_headers = "") {
  testing::TcpClient client(server.port());
  client.send_all("DESCRIBE " + server.url() + " RTSP/1.0\r\nCSeq: 1\r\n" + extra_headers +
                  "Accept: application/sdp\r\n\r\n");
  std::string reply;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (reply.find("\r\n\r\n") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline && !client.eof())
    client.receive(reply, 100ms);
  return reply;
}

TEST(RtspAccess, WithoutCredentialsEveryClientIsChallenged) {
  RtspServerConfig config = ephemeral();
  config.user = "viewer";
  config.password = "s3cret";
  RtspServer server(config);
  const Feeder feeder(server);
  const std::string anonymous = describe(server);
  EXPECT_EQ(anonymous.rfind("RTSP/1.0 401", 0), 0u) << anonymous;
  EXPECT_NE(anonymous.find("WWW-Authenticate: Basic"), std::string::npos) << anonymous;
  // "viewer:s3cret" and "viewer:wrong" in base64.
  const std::string good = describe(server, "Authorization: Basic dmlld2VyOnMzY3JldA==\r\n");
  EXPECT_EQ(good.rfind("RTSP/1.0 200", 0), 0u) << good;
  const std::string bad = describe(server, "Authorization: Basic dmlld2VyOndyb25n\r\n");
  EXPECT_EQ(bad.rfind("RTSP/1.0 401", 0), 0u) << bad;
  // Without credentials configured the stream stays open to the address, as before.
  RtspServer open(ephemeral());
  const Feeder open_feeder(open);
  const std::string plain = describe(open);
  EXPECT_EQ(plain.rfind("RTSP/1.0 200", 0), 0u) << plain;
}

TEST(RtspAccess, APlayerWithTheCredentialsInItsUrlWatches) {
  RtspServerConfig config = ephemeral();
  config.user = "viewer";
  config.password = "s3cret";
  RtspServer server(config);
  const Feeder feeder(server);
  const std::string url =
      "rtsp://viewer:s3cret@127.0.0.1:" + std::to_string(server.port()) + "/test";
  testing::RtspTestClient player(url, "tcp");
  EXPECT_TRUE(player.next(10s).has_value()) << player.ended();
  testing::RtspTestClient intruder(server.url(), "tcp");
  EXPECT_FALSE(intruder.next(2s).has_value());
}

TEST(RtspAccess, SessionsBeyondTheCapAreRefused) {
  RtspServerConfig config = ephemeral();
  config.max_sessions = 1;
  RtspServer server(config);
  const Feeder feeder(server);
  testing::RtspTestClient first(server.url(), "tcp");
  ASSERT_TRUE(first.next(10s).has_value()) << first.ended();
  testing::RtspTestClient second(server.url(), "tcp");
  EXPECT_FALSE(second.next(3s).has_value()) << "a second session past max_sessions = 1";
  EXPECT_TRUE(first.next(2s).has_value()) << "the first keeps playing";
}

}  // namespace
}  // namespace probeless
