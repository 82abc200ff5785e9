// /metrics (issue #22 item 3): scraped over loopback like Prometheus does, every line checked
// against the text exposition format, and values against what /status says.
#include "app/outputs/http_metrics.hpp"

#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "app/outputs/jpeg_encoder.hpp"
#include "http_test_client.hpp"
#include "test_images.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;
using testing::http_get;

// The shape of Pipeline::status() (app/pipeline/pipeline.cpp), abridged.
nlohmann::json pipeline_status() {
  return nlohmann::json::parse(R"({
    "state": "running", "fps": 29.75, "uptime_s": 12.5,
    "frames": {"processed": 371, "out": 370, "rgbd_in": 375, "rgbd_dropped": 4, "fisheye_in": 90},
    "stages": {"render": {"p50_ms": 3.25, "p99_ms": 5.5}, "encode": {"p50_ms": 2.0, "p99_ms": 2.75}},
    "sources": {"rgbd": {"name": "sim", "state": "streaming", "last_error": ""},
                "fisheye": {"name": "cam \"2\"", "state": "no_signal", "last_error": "x"}},
    "light": {"state": "running", "frames": 88, "dropped": 2, "skipped": 90, "keyframes": 3,
              "keyframes_dropped": 1},
    "tracking": {"state": "tracking", "keyframes": 5, "lost_count": 0,
                 "anchor": {"kind": "rig", "found": true}},
    "watchdog": {"threads": []}
  })");
}

struct Scrape {
  std::map<std::string, double> samples;  // "name{labels}" -> value
  std::map<std::string, std::string> types;
};

// Checks every line against the exposition grammar (text format 0.0.4) and that each family
// has one HELP and one TYPE before its samples, which are together.
Scrape parse_exposition(const std::string& text) {
  static const std::string name = "[a-zA-Z_:][a-zA-Z0-9_:]*";
  static const std::string label = "[a-zA-Z_][a-zA-Z0-9_]*=\"(\\\\[\\\\\"n]|[^\"\\\\\\n])*\"";
  static const std::regex help("# HELP (" + name + ") .*");
  static const std::regex type("# TYPE (" + name + ") (gauge|counter)");
  static const std::regex sample("(" + name + ")(\\{" + label + "(," + label +
                                 ")*\\})? (NaN|[+-]Inf|-?[0-9]+(\\.[0-9]+)?([eE][+-]?[0-9]+)?)");
  Scrape scrape;
  std::set<std::string> helped, done;
  std::string current;  // the family whose samples are being read
  std::istringstream lines(text);
  std::string line;
  EXPECT_EQ(text.back(), '\n');
  while (std::getline(lines, line)) {
    std::smatch m;
    if (std::regex_match(line, m, help)) {
      EXPECT_TRUE(helped.insert(m[1]).second) << "second HELP: " << line;
      if (!current.empty()) done.insert(current);
      current = m[1];
      EXPECT_FALSE(done.count(current)) << "family split: " << line;
    } else if (std::regex_match(line, m, type)) {
      EXPECT_EQ(m[1], current) << "TYPE without its HELP just before: " << line;
      EXPECT_TRUE(scrape.types.emplace(m[1], m[2]).second) << "second TYPE: " << line;
      if (m[2] == "counter") {
        EXPECT_TRUE(std::string(m[1]).ends_with("_total")) << line;
      }
    } else if (std::regex_match(line, m, sample)) {
      EXPECT_EQ(m[1], current) << "sample outside its family: " << line;
      const auto space = line.rfind(' ');
      scrape.samples[line.substr(0, space)] = std::stod(line.substr(space + 1));
    } else {
      ADD_FAILURE() << "not in the exposition format: " << line;
    }
  }
  for (const auto& h : helped) EXPECT_TRUE(scrape.types.count(h)) << h << " has no TYPE";
  return scrape;
}

TEST(HttpMetrics, ScrapeIsInTheExpositionFormatAndAgreesWithStatus) {
  HttpServerConfig config;
  config.port = 0;
  HttpServer server(config, pipeline_status);
  JpegEncoder encoder(80);
  server.publish({encoder.encode_shared(testing::gradient_image(64, 48, 1)), monotonic_now_ns()});
  testing::MjpegReader viewer(server.port(), "/stream");
  ASSERT_TRUE(viewer.next(5s));

  const auto r = http_get(server.port(), "/metrics");
  ASSERT_EQ(r.head.status, 200);
  EXPECT_EQ(r.head.get("content-type"), "text/plain; version=0.0.4; charset=utf-8");
  const Scrape scrape = parse_exposition(r.body);
  const nlohmann::json status = nlohmann::json::parse(http_get(server.port(), "/status").body);

  const auto& s = scrape.samples;
  EXPECT_EQ(s.at("probeless_frames_per_second"), status["fps"].get<double>());
  EXPECT_EQ(s.at("probeless_stage_duration_seconds{stage=\"render\",quantile=\"0.5\"}"),
            status["stages"]["render"]["p50_ms"].get<double>() / 1000);
  EXPECT_EQ(s.at("probeless_stage_duration_seconds{stage=\"encode\",quantile=\"0.99\"}"),
            status["stages"]["encode"]["p99_ms"].get<double>() / 1000);
  EXPECT_EQ(s.at("probeless_rgbd_frames_dropped_total"), status["frames"]["rgbd_dropped"]);
  EXPECT_EQ(s.at("probeless_light_frames_dropped_total"), status["light"]["dropped"]);
  EXPECT_EQ(s.at("probeless_light_frames_skipped_total"), status["light"]["skipped"]);
  EXPECT_EQ(s.at("probeless_http_stream_clients"), status["http"]["clients"]);
  EXPECT_EQ(s.at("probeless_http_stream_clients"), 1);
  EXPECT_EQ(s.at("probeless_http_frames_published_total"), status["http"]["frames_published"]);
  EXPECT_GT(s.at("probeless_http_sent_bytes_total"), 0);
  EXPECT_EQ(s.at("probeless_source_online{source=\"rgbd\"}"), 1);
  EXPECT_EQ(s.at("probeless_source_online{source=\"fisheye\"}"), 0);
  EXPECT_EQ(s.at("probeless_source_state{source=\"fisheye\",state=\"no_signal\"}"), 1);
  EXPECT_EQ(s.at("probeless_source_state{source=\"fisheye\",state=\"streaming\"}"), 0);
  EXPECT_EQ(s.at("probeless_light_state{state=\"running\"}"), 1);
  EXPECT_EQ(s.at("probeless_tracking_state{state=\"tracking\"}"), 1);
  EXPECT_EQ(s.at("probeless_tracking_anchor_found"), 1);
  EXPECT_EQ(s.at("probeless_service_state{state=\"running\"}"), 1);
  EXPECT_EQ(scrape.types.at("probeless_frames_out_total"), "counter");
  EXPECT_EQ(scrape.types.at("probeless_frames_per_second"), "gauge");

  // Wrong methods and HEAD as on every route.
  EXPECT_EQ(testing::http_request(server.port(), "POST", "/metrics").head.status, 405);
  EXPECT_EQ(testing::http_request(server.port(), "HEAD", "/metrics").body, "");
}

TEST(HttpMetrics, WithoutAStatusOnlyTheServersOwnCountersAreExposed) {
  HttpServerConfig config;
  config.port = 0;
  HttpServer server(config);
  const Scrape scrape = parse_exposition(http_get(server.port(), "/metrics").body);
  for (const auto& [name, type] : scrape.types)
    EXPECT_TRUE(name.starts_with("probeless_http_")) << name;
  EXPECT_EQ(scrape.samples.at("probeless_http_stream_clients"), 0);
}

TEST(HttpMetrics, LabelValuesAndOddNumbersAreEscapedAndSpelled) {
  MetricsText m;
  m.add("probeless_x", MetricType::Gauge, "a \\ help\nline", {{"name", "a \"q\" \\ \n"}}, 0.1);
  m.add("probeless_x", MetricType::Gauge, "ignored: the family has its HELP", {}, 1.0 / 0.0);
  m.add("probeless_y_total", MetricType::Counter, "y", {}, 12345678901234.0);
  EXPECT_EQ(m.text(),
            "# HELP probeless_x a \\\\ help\\nline\n"
            "# TYPE probeless_x gauge\n"
            "probeless_x{name=\"a \\\"q\\\" \\\\ \\n\"} 0.1\n"
            "probeless_x +Inf\n"
            "# HELP probeless_y_total y\n"
            "# TYPE probeless_y_total counter\n"
            "probeless_y_total 12345678901234\n");
  parse_exposition(m.text());
}

}  // namespace
}  // namespace probeless
