// The WebRTC output with a real WebRTC client (GStreamer's webrtcbin, lab::WhepReceiver) over
// loopback: frames pushed come out decoded with their pictures, and a client that vanishes
// without the DELETE (a closed tab, a lost network) has its session ended by the service
// itself, so that abandoned sessions cannot fill [webrtc] max_sessions. Skipped without
// GStreamer's WebRTC plugins.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "app/outputs/http_server.hpp"
#include "app/outputs/webrtc_output.hpp"
#include "lab/bench/whep_receiver.hpp"
#include "test_images.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

TEST(WebRtcSession, AClientThatVanishesWithoutDeleteIsEnded) {
  if (const std::string missing = webrtc_missing_plugins(); !missing.empty())
    GTEST_SKIP() << "no WebRTC in this GStreamer: " << missing;
  HttpServerConfig http;
  http.port = 0;
  HttpServer server(http);
  WebRtcConfig config;
  config.disconnected_timeout_s = 3;
  auto webrtc = std::make_shared<WebRtcOutput>(config, RtspServerConfig{});
  server.set_whep(webrtc);
  std::jthread pusher([&](std::stop_token stop) {
    for (int i = 0; !stop.stop_requested(); ++i) {
      webrtc->push(std::make_shared<const ImageRGB8>(testing::gradient_image(320, 240, i)),
                   monotonic_now_ns());
      std::this_thread::sleep_for(33ms);
    }
  });

  lab::WhepReceiver client(server.port());
  int decoded = 0;
  const auto until = std::chrono::steady_clock::now() + 10s;
  while (decoded < 10 && std::chrono::steady_clock::now() < until) {
    if (auto frame = client.next(500ms)) {
      EXPECT_EQ(frame->image.width(), 320);
      EXPECT_EQ(frame->image.height(), 240);
      ++decoded;
    }
  }
  ASSERT_EQ(decoded, 10) << "the client decoded no stream";
  // A client that plays on is kept well past disconnected_timeout_s: its RTCP says it is there.
  const auto playing = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() < playing + 5s) (void)client.next(100ms);
  ASSERT_EQ(webrtc->stats().sessions, 1) << "a playing client's session was ended";

  client.vanish();
  const auto vanished = std::chrono::steady_clock::now();
  while (webrtc->stats().sessions > 0 && std::chrono::steady_clock::now() < vanished + 60s)
    std::this_thread::sleep_for(100ms);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - vanished).count();
  std::cout << "session ended " << seconds << " s after its client vanished\n";
  EXPECT_EQ(webrtc->stats().sessions, 0) << "still there after " << seconds << " s";
}

}  // namespace
}  // namespace probeless
