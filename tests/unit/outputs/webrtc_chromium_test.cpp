// WebRTC as a browser plays it: headless Chromium loads the viewer page from a live server
// with the WebRTC output behind /whep, and the page must negotiate WHEP, receive the H.264
// stream over loopback and decode it: at least 25 frames in the 2 s after the first (the
// issue #22 bar; the stream is 30 fps). The page counts decoded frames itself
// (requestVideoFrameCallback) and posts them to the page that embeds it: a harness page
// that holds the viewer in an iframe and writes what it hears on its <body>, read back from
// Chromium's DOM dump. A second iframe on the never-ending MJPEG stream keeps the harness
// loading, so that Chromium dumps the DOM only at --timeout, in real time (WebRTC runs on the
// wall clock; a virtual time budget would not wait for it). Skipped when Chromium or
// GStreamer's WebRTC plugins are absent.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include "app/outputs/http_server.hpp"
#include "app/outputs/jpeg_encoder.hpp"
#include "app/outputs/webrtc_output.hpp"
#include "support/test_data.hpp"
#include "test_images.hpp"

namespace probeless {
namespace {

std::filesystem::path find_chromium() {
  for (const char* path : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(path)) return path;
  return {};
}

std::string attribute(const std::string& dom, const std::string& name) {
  std::smatch m;
  if (std::regex_search(dom, m, std::regex("<body[^>]*\\b" + name + "=\"([^\"]*)\""))) return m[1];
  return {};
}

TEST(WebRtcChromium, PlaysTheWhepStreamAt25FramesIn2Seconds) {
  const auto chromium = find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
  if (const std::string missing = webrtc_missing_plugins(); !missing.empty())
    GTEST_SKIP() << "no WebRTC in this GStreamer: " << missing;

  HttpServerConfig http_config;
  http_config.port = 0;
  HttpServer server(http_config);
  // A short silence timeout: Chromium's RTCP must keep its session for the whole page.
  WebRtcConfig config;
  config.disconnected_timeout_s = 2;
  auto webrtc = std::make_shared<WebRtcOutput>(config, RtspServerConfig{});
  server.set_whep(webrtc);

  // 30 fps of moving pictures to both outputs (the JPEG only so that a fallback to MJPEG
  // would show, and be caught by the transport check below).
  std::jthread publisher([&](std::stop_token stop) {
    JpegEncoder encoder;
    for (int i = 0; !stop.stop_requested(); ++i) {
      auto frame = std::make_shared<const ImageRGB8>(testing::gradient_image(640, 480, i));
      const TimestampNs now = monotonic_now_ns();
      webrtc->push(frame, now);
      if (i % 30 == 0) server.publish({encoder.encode_shared(*frame), now});
      std::this_thread::sleep_for(std::chrono::milliseconds(33));
    }
  });

  const auto dir = testing::scratch_dir();
  std::filesystem::create_directories(dir / "profile");
  const auto dom_file = dir / "webrtc_dom.html";
  const auto harness = dir / "harness.html";
  std::ofstream(harness) << "<!DOCTYPE html><html><body><iframe src=\"" << server.url()
                         << "/\" width=700 height=500></iframe><iframe src=\"" << server.url()
                         << "/stream\"></iframe><script>window.addEventListener('message', "
                            "(e) => Object.assign(document.body.dataset, e.data));</script>"
                            "</body></html>\n";
  // --timeout: the DOM is dumped after this much real time (WebRTC runs on the wall clock,
  // so no virtual time budget).
  const std::string command =
      "timeout 60 '" + chromium.string() +
      "' --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
      " --disable-background-networking --disable-component-update --disable-sync"
      " --autoplay-policy=no-user-gesture-required --user-data-dir='" +
      (dir / "profile").string() + "' --timeout=8000 --dump-dom 'file://" + harness.string() +
      "' > '" + dom_file.string() + "' 2> '" + (dir / "chromium.log").string() + "'";
  const auto start = std::chrono::steady_clock::now();
  const int rc = std::system(command.c_str());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  publisher.request_stop();
  publisher.join();
  ASSERT_EQ(rc, 0) << "chromium failed; see " << (dir / "chromium.log");
  std::ifstream in(dom_file);
  std::stringstream dom;
  dom << in.rdbuf();
  const std::string transport = attribute(dom.str(), "data-transport");
  const std::string frames_2s = attribute(dom.str(), "data-frames2s");
  RecordProperty("chromium_seconds", std::to_string(seconds));
  RecordProperty("frames_2s", frames_2s);
  std::cout << "chromium " << seconds << " s, transport " << transport << ", frames in 2 s "
            << frames_2s << ", frames " << attribute(dom.str(), "data-frames") << "\n";
  std::cout << "webrtc: " << to_json(webrtc->stats()).dump() << "\n";
  ASSERT_EQ(transport, "webrtc") << "the page fell back; DOM dump: " << dom_file;
  ASSERT_FALSE(frames_2s.empty());
  EXPECT_GE(std::stoi(frames_2s), 25);
  // Frames for longer than the silence timeout: the session was not ended under the page.
  EXPECT_GE(std::stoi(attribute(dom.str(), "data-frames")), 90);
  const WebRtcStats stats = webrtc->stats();
  EXPECT_EQ(stats.sessions_total, 1u);
  EXPECT_GT(stats.frames_encoded, 25u);
}

}  // namespace
}  // namespace probeless
