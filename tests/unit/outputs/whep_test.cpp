// WHEP on the HTTP server (app/outputs/http_whep.cpp) and the offer checks before it
// (app/outputs/whep_offer.hpp): every bad input gets its clear 4xx and nothing is built for
// it; a good offer gets 201, the answer and a Location that DELETE ends. The endpoint is a
// fake here except in the session-cap test, which runs the real WebRTC output (skipped
// without GStreamer's WebRTC plugins). Chromium's own offer (chromium_offer.sdp, Chromium
// 156's recvonly video offer) is the good one.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>

#include "app/outputs/http_server.hpp"
#include "app/outputs/webrtc_output.hpp"
#include "app/outputs/whep_offer.hpp"
#include "http_test_client.hpp"

namespace probeless {
namespace {

using testing::http_exchange;
using testing::http_request;
using testing::HttpResponse;

std::string chromium_offer() {
  std::ifstream in(std::filesystem::path(PROBELESS_TEST_SOURCE_DIR) / "chromium_offer.sdp",
                   std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// `line` (a whole SDP line, without CRLF) replaced by `with` (may be empty: removed).
std::string edit(std::string sdp, const std::string& line, const std::string& with) {
  const auto at = sdp.find(line + "\r\n");
  if (at == std::string::npos) throw std::runtime_error("no line " + line);
  sdp.replace(at, line.size() + 2, with.empty() ? "" : with + "\r\n");
  return sdp;
}

std::string line_starting(const std::string& sdp, const std::string& prefix) {
  const auto at = sdp.find("\r\n" + prefix);
  if (at == std::string::npos) throw std::runtime_error("no line " + prefix);
  return sdp.substr(at + 2, sdp.find("\r\n", at + 2) - at - 2);
}

TEST(WhepOffer, ChoosesChromiumsConstrainedBaselineH264) {
  const WhepOfferChoice c = choose_whep_format(chromium_offer());
  EXPECT_EQ(c.payload_type, 108);  // "H264/90000 ... packetization-mode=1;profile-level-id=42e01f"
  EXPECT_EQ(c.profile_level_id, "42e01f");
}

TEST(WhepOffer, RefusesWhatCannotBeServedWithTheReason) {
  const std::string offer = chromium_offer();
  const auto refused = [](const std::string& sdp, const std::string& reason) {
    try {
      choose_whep_format(sdp);
      ADD_FAILURE() << "accepted; expected: " << reason;
    } catch (const WhepOfferError& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  refused("", "empty");
  refused("hello", "v=0");
  refused("v=0\r\n\x01\x02\xff garbage", "");
  refused(std::string(kMaxWhepOfferBytes + 1, 'v'), "too large");
  refused("v=0\r\no=- 1 1 IN IP4 0.0.0.0\r\ns=-\r\nt=0 0\r\n", "no m=video");
  refused(offer + "m=audio 9 UDP/TLS/RTP/SAVPF 111\r\n", "only one video");
  refused(edit(offer, "a=recvonly", "a=sendonly"), "recvonly or sendrecv");
  refused(edit(offer, line_starting(offer, "a=ice-pwd:"), ""), "ICE credentials");
  refused(edit(offer, line_starting(offer, "a=fingerprint:"), ""), "fingerprint");
  std::string no_h264 = offer;
  for (const char* pt : {"102", "104", "108", "114", "116", "39", "41", "43"})
    no_h264 = edit(no_h264, line_starting(no_h264, std::string("a=rtpmap:") + pt + " "), "");
  refused(no_h264, "no H.264");
}

// Answers every offer with a fixed SDP and remembers the sessions it made.
class FakeEndpoint : public WhepEndpoint {
 public:
  void offer(std::string sdp, Done done) override {
    offers++;
    last_offer = std::move(sdp);
    WhepAnswer a;
    a.sdp = "v=0\r\nfake answer\r\n";
    a.session_id = "0123abcd";
    std::lock_guard lock(mutex);
    open = true;
    done(std::move(a));  // any thread: here, the caller's
  }
  bool close_session(std::string_view id) override {
    std::lock_guard lock(mutex);
    if (id != "0123abcd" || !open) return false;
    open = false;
    return true;
  }
  std::atomic<int> offers{0};
  std::string last_offer;
  std::mutex mutex;
  bool open = false;
};

HttpResponse post(int port, const std::string& path, const std::string& type,
                  const std::string& body) {
  std::string request = "POST " + path + " HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n";
  if (!type.empty()) request += "Content-Type: " + type + "\r\n";
  request += "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
  return http_exchange(port, request);
}

struct WhepServer : ::testing::Test {
  WhepServer()
      : server([] {
          HttpServerConfig c;
          c.port = 0;
          c.access.cors_origin = "https://dash.example";
          return c;
        }()) {
    server.set_whep(endpoint);
  }
  std::shared_ptr<FakeEndpoint> endpoint = std::make_shared<FakeEndpoint>();
  HttpServer server;
};

TEST_F(WhepServer, AnswersAnOfferWith201AndTheSessionsLocation) {
  const auto r = post(server.port(), "/whep", "application/sdp", chromium_offer());
  ASSERT_EQ(r.head.status, 201) << r.body;
  EXPECT_EQ(r.head.get("content-type"), "application/sdp");
  EXPECT_EQ(r.head.get("location"), "/whep/0123abcd");
  EXPECT_EQ(r.head.get("access-control-allow-origin"), "https://dash.example");
  EXPECT_EQ(r.head.get("access-control-expose-headers"), "Location");
  EXPECT_EQ(r.body, "v=0\r\nfake answer\r\n");
  EXPECT_EQ(endpoint->last_offer, chromium_offer());
  // mediamtx's path style, and a content type with a parameter.
  const auto m =
      post(server.port(), "/probeless/whep", "Application/SDP; charset=utf-8", chromium_offer());
  EXPECT_EQ(m.head.status, 201);
  EXPECT_EQ(m.head.get("location"), "/probeless/whep/0123abcd");

  EXPECT_EQ(http_request(server.port(), "DELETE", "/whep/0123abcd").head.status, 200);
  EXPECT_EQ(http_request(server.port(), "DELETE", "/whep/0123abcd").head.status, 404);
}

TEST_F(WhepServer, BadRequestsGetAClear4xxAndReachNoEndpoint) {
  const int port = server.port();
  const std::string offer = chromium_offer();
  EXPECT_EQ(post(port, "/whep", "application/sdp", "").head.status, 400);
  const auto wrong_type = post(port, "/whep", "application/json", offer);
  EXPECT_EQ(wrong_type.head.status, 415);
  EXPECT_NE(wrong_type.body.find("application/sdp"), std::string::npos);
  EXPECT_EQ(post(port, "/whep", "", offer).head.status, 415);
  const auto garbage = post(port, "/whep", "application/sdp", "v=0\r\nnot really sdp\x01\r\n");
  EXPECT_EQ(garbage.head.status, 400);
  EXPECT_NE(garbage.body.find("bad offer"), std::string::npos) << garbage.body;
  // Over the limit: libevent refuses the Content-Length before reading the body.
  EXPECT_EQ(
      post(port, "/whep", "application/sdp", std::string(kMaxWhepOfferBytes + 1, 'v')).head.status,
      413);
  // A Content-Length far beyond what is sent: refused on the header alone.
  const auto huge =
      http_exchange(port,
                    "POST /whep HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n"
                    "Content-Type: application/sdp\r\nContent-Length: 4000000000\r\n\r\n");
  EXPECT_EQ(huge.head.status, 413);
  EXPECT_EQ(http_request(port, "DELETE", "/whep/ffff").head.status, 404);
  EXPECT_EQ(http_request(port, "DELETE", "/whep/not-hex").head.status, 404);
  EXPECT_EQ(http_request(port, "GET", "/whep").head.status, 405);
  EXPECT_EQ(http_request(port, "PATCH", "/whep/0123abcd").head.status, 405);  // no trickle
  EXPECT_EQ(http_request(port, "POST", "/a/b/whep").head.status, 404);
  EXPECT_EQ(endpoint->offers, 0);
}

TEST_F(WhepServer, OptionsAnswersTheCorsPreflight) {
  const auto r = http_request(server.port(), "OPTIONS", "/whep", std::chrono::seconds(5),
                              "Host: localhost\r\nOrigin: https://dash.example\r\n"
                              "Access-Control-Request-Method: POST\r\n");
  EXPECT_EQ(r.head.status, 200);
  EXPECT_EQ(r.head.get("allow"), "OPTIONS, POST");
  EXPECT_EQ(r.head.get("access-control-allow-methods"), "OPTIONS, POST");
  EXPECT_EQ(r.head.get("access-control-allow-headers"), "Authorization, Content-Type");
  EXPECT_EQ(r.head.get("access-control-allow-origin"), "https://dash.example");
  EXPECT_EQ(r.head.get("accept-post"), "application/sdp");
  EXPECT_EQ(http_request(server.port(), "OPTIONS", "/whep/0123abcd").head.get("allow"),
            "OPTIONS, DELETE");
}

TEST(WhepServerOff, WhepIs404WithoutTheWebRtcOutput) {
  HttpServerConfig c;
  c.port = 0;
  HttpServer server(c);
  const auto r = post(server.port(), "/whep", "application/sdp", chromium_offer());
  EXPECT_EQ(r.head.status, 404);
  EXPECT_NE(r.body.find("[webrtc]"), std::string::npos);
}

// The real output: Chromium's offer is answered (a session that waits for a client that
// never comes), the next one is over the cap.
TEST(WhepSessions, OffersBeyondMaxSessionsGet503) {
  if (const std::string missing = webrtc_missing_plugins(); !missing.empty())
    GTEST_SKIP() << "no WebRTC in this GStreamer: " << missing;
  HttpServerConfig c;
  c.port = 0;
  HttpServer server(c);
  WebRtcConfig config;
  config.max_sessions = 1;
  auto webrtc = std::make_shared<WebRtcOutput>(config, RtspServerConfig{});
  server.set_whep(webrtc);
  const auto first = post(server.port(), "/whep", "application/sdp", chromium_offer());
  ASSERT_EQ(first.head.status, 201) << first.body;
  EXPECT_NE(first.body.find("a=candidate:"), std::string::npos) << first.body;
  EXPECT_NE(first.body.find(" 127.0.0.1 "), std::string::npos) << first.body;  // loopback only
  EXPECT_NE(first.body.find("a=rtpmap:108 H264/90000"), std::string::npos) << first.body;
  const auto second = post(server.port(), "/whep", "application/sdp", chromium_offer());
  EXPECT_EQ(second.head.status, 503) << second.body;
  EXPECT_EQ(second.head.get("retry-after"), "5");
  EXPECT_EQ(webrtc->stats().sessions, 1);
  ASSERT_EQ(http_request(server.port(), "DELETE", first.head.get("location")).head.status, 200);
  const auto third = post(server.port(), "/whep", "application/sdp", chromium_offer());
  EXPECT_EQ(third.head.status, 201) << third.body;
}

}  // namespace
}  // namespace probeless
