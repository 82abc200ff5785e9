// The viewer page as a browser shows it: headless Chromium loads "/" from a live server and
// the screenshot must show the stream's picture. Skipped when Chromium is not installed
// (Debian's `chromium` package; not in scripts/packages.txt).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "app/outputs/http_server.hpp"
#include "app/outputs/jpeg_encoder.hpp"
#include "drivers/io/png.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

std::filesystem::path find_chromium() {
  for (const char* name : {"chromium", "chromium-browser"}) {
    for (const char* dir : {"/usr/bin", "/usr/local/bin", "/snap/bin"}) {
      const std::filesystem::path p = std::filesystem::path(dir) / name;
      if (std::filesystem::exists(p)) return p;
    }
  }
  return {};
}

TEST(ViewerPage, ChromiumShowsTheStream) {
  const auto chromium = find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";

  HttpServerConfig config;
  config.port = 0;
  HttpServer server(config, [] { return nlohmann::json{{"fps", 30.0}}; });
  // A picture no page chrome has: pure magenta.
  JpegEncoder encoder;
  ImageRGB8 magenta(640, 480);
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      magenta.at(x, y, 0) = 255;
      magenta.at(x, y, 2) = 255;
    }
  }
  const auto frame = encoder.encode_shared(magenta);
  std::jthread publisher([&](std::stop_token stop) {
    while (!stop.stop_requested()) {
      server.publish({frame, monotonic_now_ns()});
      std::this_thread::sleep_for(std::chrono::milliseconds(33));
    }
  });

  const auto dir = testing::scratch_dir();
  const auto shot = dir / "viewer.png";
  std::filesystem::create_directories(dir / "profile");
  const std::string command =
      "timeout 120 '" + chromium.string() +
      "' --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
      " --disable-background-networking --disable-component-update --disable-sync"
      " --user-data-dir='" +
      (dir / "profile").string() + "' --screenshot='" + shot.string() +
      "' --window-size=1000,700 --virtual-time-budget=3000 " + server.url() + "/ > '" +
      (dir / "chromium.log").string() + "' 2>&1";
  const auto start = std::chrono::steady_clock::now();
  const int rc = std::system(command.c_str());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("chromium_seconds", std::to_string(seconds));
  ASSERT_EQ(rc, 0) << "chromium failed; see " << (dir / "chromium.log");
  ASSERT_TRUE(std::filesystem::exists(shot));

  const ImageRGB8 image = read_png_rgb8(shot);
  std::size_t magenta_pixels = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      if (image.at(x, y, 0) > 230 && image.at(x, y, 1) < 30 && image.at(x, y, 2) > 230) {
        ++magenta_pixels;
      }
    }
  }
  // The 640x480 <img> covers 44% of a 1000x700 window; ask for most of it.
  EXPECT_GT(magenta_pixels, 640u * 480u * 8 / 10)
      << "the stream is not on the page; screenshot: " << shot;
  EXPECT_GT(server.stats().requests, 1u);  // the page, the stream, status polls
}

}  // namespace
}  // namespace probeless
