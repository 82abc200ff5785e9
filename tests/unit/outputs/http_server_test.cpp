#include "app/outputs/http_server.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <set>
#include <thread>
#include <utility>

#include "app/outputs/jpeg_encoder.hpp"
#include "eventually.hpp"
#include "http_test_client.hpp"
#include "test_images.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;
using testing::http_get;
using testing::http_request;
using testing::MjpegReader;

HttpServerConfig ephemeral() {
  HttpServerConfig config;
  config.port = 0;
  return config;
}

EncodedFrame encoded(const ImageRGB8& image, TimestampNs t, int quality = 80) {
  JpegEncoder encoder(quality);
  return {encoder.encode_shared(image), t};
}

// Publishes a fixed set of frames round-robin at a steady period on its own thread, the
// way the pipeline's encoder thread would.
class Publisher {
 public:
  Publisher(HttpServer& server, std::vector<EncodedFrame> frames, std::chrono::milliseconds period)
      : thread_([this, &server, frames = std::move(frames), period](std::stop_token stop) {
          for (std::size_t i = 0; !stop.stop_requested(); ++i) {
            EncodedFrame f = frames[i % frames.size()];
            f.timestamp_ns = monotonic_now_ns();
            server.publish(std::move(f));
            ++published_;
            std::this_thread::sleep_for(period);
          }
        }) {}
  std::uint64_t published() const { return published_; }

 private:
  std::atomic<std::uint64_t> published_{0};
  std::jthread thread_;
};

// Waits (generously) for a condition that depends on the server's thread.
using testing::eventually;

TEST(HttpServer, BindsAnEphemeralPortOnLoopback) {
  HttpServer server(ephemeral());
  EXPECT_GT(server.port(), 0);
  EXPECT_EQ(server.url(), "http://127.0.0.1:" + std::to_string(server.port()));
}

TEST(HttpServer, ABusyPortIsAnErrorNamingTheAddress) {
  HttpServer first(ephemeral());
  HttpServerConfig config;
  config.port = first.port();
  try {
    HttpServer second(config);
    FAIL() << "bound a busy port";
  } catch (const HttpServerError& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(first.port())),
              std::string::npos)
        << e.what();
  }
  config.address = "not an address";
  EXPECT_THROW(HttpServer{config}, HttpServerError);
}

// Before the first frame a placeholder, as ustreamer does (http_compat_test.cpp checks it).
TEST(HttpServer, SnapshotIsAPlaceholderUntilTheFirstFrameThenTheLatestJpeg) {
  HttpServer server(ephemeral());
  auto r = http_get(server.port(), "/snapshot");
  EXPECT_EQ(r.head.status, 200);
  EXPECT_EQ(r.head.get("x-ustreamer-online"), "false");

  server.publish(encoded(testing::gradient_image(320, 240, 1), 1'500'000'000));
  server.publish(encoded(testing::gradient_image(640, 480, 2), 2'250'000'000));
  r = http_get(server.port(), "/snapshot");
  ASSERT_EQ(r.head.status, 200);
  EXPECT_EQ(r.head.get("content-type"), "image/jpeg");
  EXPECT_NE(r.head.get("cache-control").find("no-store"), std::string::npos);
  EXPECT_EQ(r.head.get("x-timestamp-monotonic"), "2.250000");
  EXPECT_EQ(r.head.get("x-ustreamer-online"), "true");
  JpegDecoder decoder;
  const ImageRGB8 image =
      decoder.decode({reinterpret_cast<const std::uint8_t*>(r.body.data()), r.body.size()});
  EXPECT_EQ(image.width(), 640);
  EXPECT_EQ(image.height(), 480);

  // mjpg-streamer's URL for the same.
  r = http_get(server.port(), "/?action=snapshot");
  EXPECT_EQ(r.head.status, 200);
  EXPECT_EQ(r.head.get("content-type"), "image/jpeg");
}

void expect_valid_parts(MjpegReader& reader, int count, int width, int height) {
  JpegDecoder decoder;
  std::set<std::string> timestamps;
  // A reader that connects before the publisher's first frame gets ustreamer's placeholder
  // first (HttpCompat.BeforeTheFirstFrameTheStreamShowsThePlaceholder): 640x480, which no
  // caller here publishes.
  bool first = true;
  for (int i = 0; i < count; ++i) {
    auto part = reader.next(5s);
    ASSERT_TRUE(part) << "part " << i;
    if (std::exchange(first, false)) {
      const ImageRGB8 image = decoder.decode(
          {reinterpret_cast<const std::uint8_t*>(part->body.data()), part->body.size()});
      if (image.width() == 640 && image.height() == 480 && width != 640) {
        --i;
        continue;
      }
    }
    EXPECT_EQ(part->headers["content-type"], "image/jpeg");
    EXPECT_EQ(std::stoul(part->headers["content-length"]), part->body.size());
    ASSERT_TRUE(part->headers.count("x-timestamp"));
    timestamps.insert(part->headers["x-timestamp"]);
    const ImageRGB8 image = decoder.decode(
        {reinterpret_cast<const std::uint8_t*>(part->body.data()), part->body.size()});
    EXPECT_EQ(image.width(), width);
    EXPECT_EQ(image.height(), height);
  }
  EXPECT_EQ(timestamps.size(), static_cast<std::size_t>(count));  // a new frame each time
}

TEST(HttpServer, StreamsMultipartJpegChunkedToHttp11Clients) {
  HttpServer server(ephemeral());
  Publisher publisher(server, {encoded(testing::gradient_image(320, 240, 1), 0)}, 10ms);
  MjpegReader reader(server.port(), "/stream");
  const auto& head = reader.head();
  EXPECT_EQ(head.status, 200);
  EXPECT_EQ(head.get("content-type"), "multipart/x-mixed-replace;boundary=boundarydonotcross");
  EXPECT_NE(head.get("cache-control").find("no-store"), std::string::npos);
  EXPECT_TRUE(reader.chunked());
  expect_valid_parts(reader, 5, 320, 240);
  EXPECT_EQ(server.stats().stream_clients.size(), 1u);
}

TEST(HttpServer, StreamsRawMultipartToHttp10ClientsAtTheMjpgStreamerUrl) {
  HttpServer server(ephemeral());
  Publisher publisher(server, {encoded(testing::gradient_image(160, 120, 1), 0)}, 10ms);
  MjpegReader reader(server.port(), "/?action=stream", /*http10=*/true);
  EXPECT_EQ(reader.head().status, 200);
  EXPECT_FALSE(reader.chunked());
  expect_valid_parts(reader, 5, 160, 120);
}

TEST(HttpServer, ANewStreamClientGetsTheCurrentFrameAtOnce) {
  HttpServer server(ephemeral());
  server.publish(encoded(testing::gradient_image(64, 48), 42'000'000'000));
  MjpegReader reader(server.port(), "/stream");
  auto part = reader.next(5s);  // nothing else is published
  ASSERT_TRUE(part);
  EXPECT_EQ(part->headers["x-timestamp-monotonic"], "42.000000");
}

TEST(HttpServer, StatusMergesTheCallbackWithServerStats) {
  HttpServer server(ephemeral(), [] {
    return nlohmann::json{{"fps", 29.5},
                          {"stages", {{"matte", {{"p50_ms", 3.0}, {"p99_ms", 5.0}}}}},
                          {"sources", {{"rgbd", {{"state", "streaming"}}}}}};
  });
  server.publish(encoded(testing::gradient_image(64, 48), 1));
  MjpegReader viewer(server.port(), "/stream");
  ASSERT_TRUE(viewer.next(5s));
  const auto r = http_get(server.port(), "/status");
  ASSERT_EQ(r.head.status, 200);
  EXPECT_EQ(r.head.get("content-type"), "application/json");
  EXPECT_NE(r.head.get("cache-control").find("no-store"), std::string::npos);
  const auto status = nlohmann::json::parse(r.body);
  EXPECT_DOUBLE_EQ(status["fps"].get<double>(), 29.5);
  EXPECT_EQ(status["sources"]["rgbd"]["state"], "streaming");
  EXPECT_DOUBLE_EQ(status["stages"]["matte"]["p99_ms"].get<double>(), 5.0);
  const auto& http = status["http"];
  EXPECT_EQ(http["clients"], 1);
  EXPECT_EQ(http["frames_published"], 1);
  EXPECT_GT(http["bytes_sent"].get<std::uint64_t>(), 0u);
  ASSERT_EQ(http["stream_clients"].size(), 1u);
  EXPECT_EQ(http["stream_clients"][0]["frames_sent"], 1);
  EXPECT_EQ(http["stream_clients"][0]["drops"], 0);
  EXPECT_NE(http["stream_clients"][0]["peer"].get<std::string>().find("127.0.0.1:"),
            std::string::npos);
}

TEST(HttpServer, StatusWithoutCallbackOrWithAFailingOne) {
  {
    HttpServer server(ephemeral());
    const auto status = nlohmann::json::parse(http_get(server.port(), "/status").body);
    EXPECT_EQ(status["http"]["clients"], 0);
  }
  {
    HttpServer server(ephemeral(), [] { return nlohmann::json(7); });
    const auto status = nlohmann::json::parse(http_get(server.port(), "/status").body);
    EXPECT_EQ(status["service"], 7);
  }
  {
    HttpServer server(ephemeral(), []() -> nlohmann::json { throw std::runtime_error("boom"); });
    const auto r = http_get(server.port(), "/status");
    EXPECT_EQ(r.head.status, 500);
    EXPECT_NE(r.body.find("boom"), std::string::npos);
  }
}

// A name that is not UTF-8 (a device, card or file name in last_error) used to make dump()
// throw outside the try, through libevent to std::terminate: the whole service died.
TEST(HttpServer, StatusWithInvalidUtf8IsServedWithReplacements) {
  HttpServer server(ephemeral(), [] {
    return nlohmann::json{{"last_error", "/dev/video\xff\xfe: gone"}};
  });
  const auto r = http_get(server.port(), "/status");
  ASSERT_EQ(r.head.status, 200) << r.body;
  const auto status = nlohmann::json::parse(r.body);
  EXPECT_EQ(status["last_error"], "/dev/video\uFFFD\uFFFD: gone");
  EXPECT_EQ(http_get(server.port(), "/status").head.status, 200);  // still serving
}

TEST(HttpServer, ServesTheViewerPage) {
  HttpServer server(ephemeral());
  const auto r = http_get(server.port(), "/");
  ASSERT_EQ(r.head.status, 200);
  EXPECT_EQ(r.head.get("content-type"), "text/html; charset=utf-8");
  // WebRTC through WHEP first, the MJPEG stream as the fallback (viewer_page.cpp).
  EXPECT_NE(r.body.find("<img id=\"view\""), std::string::npos);
  EXPECT_NE(r.body.find("view.src = \"/stream\""), std::string::npos);
  EXPECT_NE(r.body.find("fetch(\"/whep\""), std::string::npos);
  EXPECT_NE(r.body.find("fetch(\"/status\""), std::string::npos);
  EXPECT_EQ(r.body.find("http://"), std::string::npos);  // no external assets
  EXPECT_EQ(r.body.find("https://"), std::string::npos);
}

// HEAD and OPTIONS are answered (ustreamer's; http_compat_test.cpp), the rest 405.
TEST(HttpServer, UnknownPathsAre404AndOtherMethods405) {
  HttpServer server(ephemeral());
  EXPECT_EQ(http_get(server.port(), "/nope").head.status, 404);
  EXPECT_EQ(http_get(server.port(), "/?action=nope").head.status, 404);
  EXPECT_EQ(http_get(server.port(), "/stream/extra").head.status, 404);
  for (const char* method : {"POST", "PUT", "DELETE", "PATCH"}) {
    const auto r = http_request(server.port(), method, "/snapshot");
    EXPECT_EQ(r.head.status, 405) << method;
    EXPECT_EQ(r.head.get("allow"), "GET, HEAD, OPTIONS") << method;
  }
  EXPECT_EQ(http_request(server.port(), "HEAD", "/nope").head.status, 404);
  EXPECT_EQ(http_request(server.port(), "OPTIONS", "/nope").head.status, 404);
  EXPECT_EQ(http_request(server.port(), "POST", "/stream").head.status, 405);
  EXPECT_EQ(http_request(server.port(), "POST", "/nope").head.status, 404);
}

// Frames the reading client receives in `duration`, counted as distinct timestamps.
std::size_t frames_received(int port, std::chrono::milliseconds duration) {
  MjpegReader reader(port, "/stream");
  std::set<std::string> seen;
  const auto end = std::chrono::steady_clock::now() + duration;
  while (std::chrono::steady_clock::now() < end) {
    if (auto part = reader.next(200ms)) seen.insert(part->headers["x-timestamp"]);
  }
  return seen.size();
}

// The slow-client policy: a client that never reads must not slow the pipeline or other
// clients. Big frames (noise) fill its socket buffers within a few frames.
TEST(HttpServer, AStalledClientDoesNotSlowOtherClients) {
  HttpServerConfig config = ephemeral();
  config.client_buffer_limit = 256 * 1024;
  HttpServer server(config);
  std::vector<EncodedFrame> frames;
  for (unsigned i = 0; i < 4; ++i) {
    frames.push_back(encoded(testing::noise_image(640, 480, i), 0, 90));
  }
  ASSERT_GT(frames[0].jpeg->size(), 200'000u);
  Publisher publisher(server, frames, 10ms);

  const std::size_t alone = frames_received(server.port(), 1500ms);
  ASSERT_GT(alone, 10u);

  testing::TcpClient stalled(server.port(), /*receive_buffer=*/4096);
  stalled.send_all("GET /stream HTTP/1.1\r\nHost: localhost\r\n\r\n");
  ASSERT_TRUE(eventually([&] { return server.stats().stream_clients.size() == 1; }));
  const std::size_t beside_stalled = frames_received(server.port(), 1500ms);
  EXPECT_GE(beside_stalled * 2, alone)
      << "alone " << alone << ", beside a stalled client " << beside_stalled;

  // The stalled client is skipped, not queued without bound.
  const HttpServerStats stats = server.stats();
  ASSERT_FALSE(stats.stream_clients.empty());
  const StreamClientStats& s = stats.stream_clients.front();
  EXPECT_GT(s.drops, 10u);
  EXPECT_LE(s.buffered_bytes, config.client_buffer_limit + 2 * frames[0].jpeg->size());
}

TEST(HttpServer, ClientsThatLeaveAreForgotten) {
  HttpServer server(ephemeral());
  Publisher publisher(server, {encoded(testing::gradient_image(64, 48), 0)}, 5ms);
  {
    MjpegReader a(server.port(), "/stream");
    MjpegReader b(server.port(), "/stream");
    ASSERT_TRUE(a.next());
    ASSERT_TRUE(b.next());
    EXPECT_EQ(server.stats().stream_clients.size(), 2u);
  }
  EXPECT_TRUE(eventually([&] { return server.stats().stream_clients.empty(); }));
  MjpegReader c(server.port(), "/stream");
  EXPECT_TRUE(c.next());
}

// A stream outlives the request timeout (no read timeout on a stream), while a client
// that accepts nothing for the stall timeout is disconnected.
TEST(HttpServer, StallTimeoutDropsDeadClientsButNotLiveOnes) {
  HttpServerConfig config = ephemeral();
  config.request_timeout = 1s;
  config.stalled_client_timeout = 1s;
  config.client_buffer_limit = 64 * 1024;
  HttpServer server(config);
  Publisher publisher(server, {encoded(testing::noise_image(320, 240, 1), 0, 90)}, 10ms);
  MjpegReader live(server.port(), "/stream");
  testing::TcpClient dead(server.port(), 4096);
  dead.send_all("GET /stream HTTP/1.1\r\nHost: localhost\r\n\r\n");
  ASSERT_TRUE(eventually([&] { return server.stats().stream_clients.size() == 2; }));
  const auto start = std::chrono::steady_clock::now();
  std::size_t parts = 0;
  while (std::chrono::steady_clock::now() - start < 3s) {
    if (live.next(1s)) ++parts;
  }
  EXPECT_GT(parts, 10u);
  EXPECT_TRUE(eventually([&] { return server.stats().stream_clients.size() == 1; }));
  EXPECT_TRUE(live.next(2s)) << "the live client was cut too";
}

TEST(HttpServer, StopIsQuickIdempotentAndSafeWithClientsConnected) {
  auto server = std::make_unique<HttpServer>(ephemeral());
  server->publish(encoded(testing::noise_image(640, 480, 5), 1, 95));
  MjpegReader reader(server->port(), "/stream");
  ASSERT_TRUE(reader.next());
  testing::TcpClient stalled(server->port(), 4096);
  stalled.send_all("GET /stream HTTP/1.1\r\nHost: localhost\r\n\r\n");
  testing::TcpClient idle(server->port());  // connected, no request yet
  ASSERT_TRUE(eventually([&] { return server->stats().stream_clients.size() == 2; }));

  const auto start = std::chrono::steady_clock::now();
  server->stop();
  const auto took = std::chrono::steady_clock::now() - start;
  EXPECT_LT(took, 1s);
  server->stop();
  server->publish(encoded(testing::gradient_image(8, 8), 2));  // after stop: ignored
  EXPECT_TRUE(server->stats().stream_clients.empty());
  server.reset();
  EXPECT_FALSE(reader.next(2s));  // the stream ended
}

TEST(HttpServer, StopRightAfterStartDoesNotHang) {
  for (int i = 0; i < 20; ++i) {
    HttpServer server(ephemeral());
    server.stop();
  }
}

TEST(HttpServer, TooManyStreamClientsGet503) {
  HttpServerConfig config = ephemeral();
  config.max_stream_clients = 1;
  HttpServer server(config);
  server.publish(encoded(testing::gradient_image(64, 48), 1));
  MjpegReader first(server.port(), "/stream");
  ASSERT_TRUE(first.next());
  EXPECT_EQ(http_get(server.port(), "/stream").head.status, 503);
}

}  // namespace
}  // namespace probeless
