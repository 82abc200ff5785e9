// ustreamer compatibility of the HTTP output (issue #22 item 2): the requests a ustreamer
// client (PiKVM's kvmd, ustreamer's own page, scripts written against its API) sends, each
// answered as ustreamer answers it, over real HTTP on loopback.
#include "app/outputs/http_compat.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>

#include "app/outputs/http_server.hpp"
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
  config.jpeg_quality = 70;
  return config;
}

EncodedFrame frame(int width, int height, TimestampNs t, bool no_signal = false) {
  JpegEncoder encoder(70);
  return {encoder.encode_shared(testing::gradient_image(width, height, 3)), t, no_signal};
}

double wall_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

ImageRGB8 decode(const std::string& bytes) {
  JpegDecoder decoder;
  return decoder.decode({reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()});
}

nlohmann::json state_of(int port) {
  const auto r = http_get(port, "/state");
  EXPECT_EQ(r.head.status, 200);
  EXPECT_EQ(r.head.get("content-type"), "application/json");
  return nlohmann::json::parse(r.body);
}

using testing::eventually;

TEST(HttpCompat, StreamOptionsAreReadAsUstreamerReadsThem) {
  const StreamOptions none = parse_stream_options(nullptr);
  EXPECT_FALSE(none.extra_headers || none.advance_headers || none.dual_final_frames);
  const StreamOptions o = parse_stream_options(
      "key=kvmd%3A%3Aa&extra_headers=1&advance_headers=0&dual_final_frames=true");
  EXPECT_EQ(o.key, "kvmd::a");
  EXPECT_TRUE(o.extra_headers);
  EXPECT_FALSE(o.advance_headers);
  EXPECT_TRUE(o.dual_final_frames);
  EXPECT_FALSE(parse_stream_options("extra_headers=x").extra_headers);
  EXPECT_EQ(parse_stream_options(("key=" + std::string(500, 'k')).c_str()).key.size(), 64u);
}

TEST(HttpCompat, TimestampsAreSecondsWithMicroseconds) {
  EXPECT_EQ(seconds_text(1'700'000'000'123'456'789), "1700000000.123456");
  EXPECT_EQ(seconds_text(-1'500'000), "-0.001500");
  const double wall = static_cast<double>(wall_clock_ns(monotonic_now_ns() - 1'000'000'000)) * 1e-9;
  EXPECT_NEAR(wall, wall_now_s() - 1.0, 0.5);
}

TEST(HttpCompat, JpegSizeComesFromTheFrameHeaderAndBadBytesAreRefused) {
  JpegEncoder encoder(80);
  const auto jpeg = encoder.encode_shared(testing::gradient_image(123, 45, 1));
  const auto size = jpeg_size(*jpeg);
  ASSERT_TRUE(size);
  EXPECT_EQ(size->width, 123);
  EXPECT_EQ(size->height, 45);
  for (std::size_t cut : {std::size_t{0}, std::size_t{1}, std::size_t{3}, std::size_t{20}}) {
    EXPECT_FALSE(jpeg_size(std::span(jpeg->data(), cut))) << cut;
  }
  std::vector<std::uint8_t> bad(*jpeg);
  bad[2] = 0x12;  // not a marker
  EXPECT_FALSE(jpeg_size(bad));
  const std::vector<std::uint8_t> huge_length{0xFF, 0xD8, 0xFF, 0xE0, 0xFF, 0xFF, 0, 0};
  EXPECT_FALSE(jpeg_size(huge_length));
}

// Before the first frame: /state says offline and /snapshot is ustreamer's blank frame.
TEST(HttpCompat, BeforeTheFirstFrameStateIsOfflineAndSnapshotAPlaceholder) {
  HttpServer server(ephemeral());
  const nlohmann::json state = state_of(server.port());
  EXPECT_EQ(state["ok"], true);
  EXPECT_EQ(state["result"]["source"]["online"], false);
  EXPECT_EQ(state["result"]["stream"]["clients"], 0);

  const auto r = http_get(server.port(), "/snapshot");
  ASSERT_EQ(r.head.status, 200);
  EXPECT_EQ(r.head.get("content-type"), "image/jpeg");
  EXPECT_EQ(r.head.get("x-ustreamer-online"), "false");
  EXPECT_NEAR(std::stod(r.head.get("x-timestamp")), wall_now_s(), 5.0);
  const ImageRGB8 image = decode(r.body);
  EXPECT_EQ(image.width(), state["result"]["source"]["resolution"]["width"].get<int>());
  EXPECT_EQ(image.height(), state["result"]["source"]["resolution"]["height"].get<int>());
}

// A viewer that connects before the first frame gets ustreamer's blank frame at once, marked
// offline, then the first real frame when it comes.
TEST(HttpCompat, BeforeTheFirstFrameTheStreamShowsThePlaceholder) {
  HttpServer server(ephemeral());
  testing::TcpClient client(server.port());
  client.send_all("GET /stream?extra_headers=1 HTTP/1.0\r\nHost: localhost\r\n\r\n");
  std::string raw;
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (std::chrono::steady_clock::now() < deadline && raw.find("\xff\xd9") == std::string::npos)
    client.receive(raw, 100ms);
  ASSERT_NE(raw.find("X-UStreamer-Online: false"), std::string::npos) << raw.substr(0, 300);
  const std::size_t soi = raw.find("\xff\xd8"), eoi = raw.find("\xff\xd9");
  ASSERT_NE(soi, std::string::npos);
  ASSERT_NE(eoi, std::string::npos);
  const ImageRGB8 blank = decode(raw.substr(soi, eoi + 2 - soi));
  EXPECT_GT(blank.width(), 0);

  const EncodedFrame f = frame(96, 64, monotonic_now_ns());
  server.publish(f);
  const std::string jpeg(f.jpeg->begin(), f.jpeg->end());
  const auto second = std::chrono::steady_clock::now() + 5s;
  while (std::chrono::steady_clock::now() < second && raw.find(jpeg) == std::string::npos)
    client.receive(raw, 100ms);
  const std::size_t at = raw.find(jpeg);
  ASSERT_NE(at, std::string::npos);
  EXPECT_GT(at, eoi);
  EXPECT_NE(raw.substr(eoi, at - eoi).find("X-UStreamer-Online: true"), std::string::npos);
}

// The requests of a ustreamer client once the source is live, in the order kvmd's streamer
// client and ustreamer's page make them, each with the answer ustreamer gives.
TEST(HttpCompat, AUstreamerClientsRequestsAreAnsweredAsUstreamerWould) {
  HttpServer server(ephemeral(), [] { return nlohmann::json{{"fps", 29.7}}; });
  const TimestampNs captured = monotonic_now_ns() - 1'000'000'000;  // a second ago
  server.publish(frame(320, 240, captured));

  struct Request {
    const char* method;
    const char* target;
    int status;
    const char* content_type;
  };
  const Request recorded[] = {
      {"GET", "/state", 200, "application/json"},
      {"GET", "/snapshot", 200, "image/jpeg"},
      {"GET", "/snapshot?key=abc", 200, "image/jpeg"},
      {"GET", "/?action=snapshot", 200, "image/jpeg"},
      {"HEAD", "/snapshot", 200, "image/jpeg"},
      {"HEAD", "/state", 200, "application/json"},
      {"HEAD", "/status", 200, "application/json"},
      {"HEAD", "/", 200, "text/html; charset=utf-8"},
      {"HEAD", "/stream", 200, "multipart/x-mixed-replace;boundary=boundarydonotcross"},
      {"OPTIONS", "/stream", 200, "text/plain; charset=utf-8"},
      {"OPTIONS", "/state", 200, "text/plain; charset=utf-8"},
      {"GET", "/favicon.ico", 404, "text/plain; charset=utf-8"},
      {"POST", "/state", 405, "text/plain; charset=utf-8"},
      {"DELETE", "/stream", 405, "text/plain; charset=utf-8"},
  };
  for (const Request& q : recorded) {
    const auto r = http_request(server.port(), q.method, q.target);
    const std::string what = std::string(q.method) + " " + q.target;
    EXPECT_EQ(r.head.status, q.status) << what;
    EXPECT_EQ(r.head.get("content-type"), q.content_type) << what;
    const std::string method = q.method;
    if (method == "HEAD" || method == "OPTIONS") {
      EXPECT_EQ(r.body, "") << what;
    }
    if (method == "OPTIONS") {
      EXPECT_EQ(r.head.get("allow"), "GET, HEAD, OPTIONS") << what;
    }
    if (method == "GET" && q.content_type == std::string("image/jpeg")) {
      EXPECT_EQ(r.head.get("x-ustreamer-online"), "true") << what;
      // The capture time on the wall clock (a second ago), the monotonic one beside it.
      EXPECT_NEAR(std::stod(r.head.get("x-timestamp")), wall_now_s() - 1.0, 0.5) << what;
      EXPECT_EQ(r.head.get("x-timestamp-monotonic"), seconds_text(captured)) << what;
      EXPECT_EQ(decode(r.body).width(), 320) << what;
    }
  }
  // HEAD tells the length GET sends; a HEAD of the stream took no stream slot.
  EXPECT_EQ(std::stoul(http_request(server.port(), "HEAD", "/snapshot").head.get("content-length")),
            http_get(server.port(), "/snapshot").body.size());
  EXPECT_TRUE(server.stats().stream_clients.empty());

  // /state against what the server really serves: the frame's size, the clients it holds.
  nlohmann::json result = state_of(server.port())["result"];
  EXPECT_EQ(result["instance_id"], "");
  EXPECT_EQ(result["encoder"]["type"], "CPU");
  EXPECT_EQ(result["encoder"]["quality"], 70);
  EXPECT_EQ(result["source"]["resolution"]["width"], 320);
  EXPECT_EQ(result["source"]["resolution"]["height"], 240);
  EXPECT_EQ(result["source"]["online"], true);
  EXPECT_EQ(result["source"]["captured_fps"], 30);  // the service's fps, rounded
  EXPECT_TRUE(result["source"]["desired_fps"].is_number());
  EXPECT_TRUE(result["stream"]["queued_fps"].is_number());
  EXPECT_EQ(result["stream"]["clients"], 0);
  EXPECT_TRUE(result["stream"]["clients_stat"].is_object());

  MjpegReader viewer(server.port(), "/stream?key=kvmd&extra_headers=1&dual_final_frames=1");
  ASSERT_TRUE(viewer.next(5s));
  result = state_of(server.port())["result"];
  EXPECT_EQ(result["stream"]["clients"], server.stats().stream_clients.size());
  ASSERT_EQ(result["stream"]["clients_stat"].size(), 1u);
  const nlohmann::json client = result["stream"]["clients_stat"].begin().value();
  EXPECT_EQ(client["key"], "kvmd");
  EXPECT_EQ(client["extra_headers"], true);
  EXPECT_EQ(client["advance_headers"], false);
  EXPECT_EQ(client["dual_final_frames"], true);

  // A NO SIGNAL frame: the source is offline, as ustreamer reports it.
  server.publish(frame(320, 240, monotonic_now_ns(), true));
  EXPECT_TRUE(
      eventually([&] { return state_of(server.port())["result"]["source"]["online"] == false; }));
  EXPECT_EQ(http_get(server.port(), "/snapshot").head.get("x-ustreamer-online"), "false");
}

TEST(HttpCompat, StreamQueryParametersAreAcceptedAndActedOn) {
  HttpServer server(ephemeral());
  server.publish(frame(160, 120, monotonic_now_ns()));
  for (const char* target : {"/stream?key=abc", "/stream?dual_final_frames=1",
                             "/?action=stream&key=abc", "/stream?extra_headers=0"}) {
    MjpegReader reader(server.port(), target);
    EXPECT_EQ(reader.head().status, 200) << target;
    const auto part = reader.next(5s);
    ASSERT_TRUE(part) << target;
    EXPECT_EQ(decode(part->body).width(), 160) << target;
    EXPECT_FALSE(part->headers.count("x-ustreamer-online")) << target;
    EXPECT_NEAR(std::stod(part->headers.at("x-timestamp")), wall_now_s(), 5.0) << target;
  }

  MjpegReader extra(server.port(), "/stream?extra_headers=1");
  const auto part = extra.next(5s);
  ASSERT_TRUE(part);
  EXPECT_EQ(part->headers.at("x-ustreamer-online"), "true");
  EXPECT_EQ(part->headers.at("x-ustreamer-width"), "160");
  EXPECT_EQ(part->headers.at("x-ustreamer-height"), "120");
  for (const char* name : {"x-ustreamer-client-fps", "x-ustreamer-grab-time",
                           "x-ustreamer-send-time", "x-ustreamer-latency"})
    EXPECT_TRUE(part->headers.count(name)) << name;
  EXPECT_GE(std::stod(part->headers.at("x-ustreamer-send-time")),
            std::stod(part->headers.at("x-ustreamer-grab-time")));
}

// advance_headers: each frame is followed at once by the next part's boundary and headers
// (no Content-Length), so a client that shows a frame when the next boundary arrives shows
// it without waiting for the next frame.
TEST(HttpCompat, AdvanceHeadersFollowEachFrame) {
  HttpServer server(ephemeral());
  const EncodedFrame f = frame(96, 64, monotonic_now_ns());
  server.publish(f);
  const std::string jpeg(f.jpeg->begin(), f.jpeg->end());
  testing::TcpClient client(server.port());
  client.send_all("GET /stream?advance_headers=1 HTTP/1.0\r\nHost: localhost\r\n\r\n");
  std::string raw;
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  std::optional<testing::HttpHead> head;
  const std::string head_start =
      "--boundarydonotcross\r\nContent-Type: image/jpeg\r\nX-Timestamp: ";
  std::size_t at = std::string::npos;
  while (std::chrono::steady_clock::now() < deadline) {
    client.receive(raw, 100ms);
    if (!head) head = testing::parse_head(raw);
    at = head ? raw.find(jpeg) : std::string::npos;
    if (at != std::string::npos && raw.find("\r\n\r\n", at + jpeg.size()) != std::string::npos)
      break;
  }
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(raw.compare(0, head_start.size(), head_start), 0) << raw.substr(0, 80);
  EXPECT_EQ(raw.substr(0, at).find("Content-Length"), std::string::npos);
  EXPECT_EQ(raw.compare(at + jpeg.size(), 2 + head_start.size(), "\r\n" + head_start), 0);
}

TEST(HttpCompat, AllowOriginIsSentOnEveryAnswer) {
  HttpServerConfig config = ephemeral();
  config.access.cors_origin = "https://kvm.local";  // --allow-origin
  HttpServer server(config);
  server.publish(frame(64, 48, monotonic_now_ns()));
  for (const char* method : {"GET", "HEAD", "OPTIONS"}) {
    for (const char* target : {"/state", "/snapshot", "/status"}) {
      const auto r = http_request(server.port(), method, target, 5s,
                                  "Host: localhost\r\nOrigin: https://kvm.local\r\n");
      EXPECT_EQ(r.head.status, 200) << method << " " << target;
      EXPECT_EQ(r.head.get("access-control-allow-origin"), "https://kvm.local")
          << method << " " << target;
    }
  }
  MjpegReader stream(server.port(), "/stream");
  EXPECT_EQ(stream.head().get("access-control-allow-origin"), "https://kvm.local");
  HttpServer plain(ephemeral());
  EXPECT_EQ(http_get(plain.port(), "/state").head.get("access-control-allow-origin"), "");
}

}  // namespace
}  // namespace probeless
