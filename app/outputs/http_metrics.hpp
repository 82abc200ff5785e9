#pragma once
// GET /metrics: what /status reports, in the Prometheus text exposition format (version
// 0.0.4, https://prometheus.io/docs/instrumenting/exposition_formats/), so a Prometheus
// server or any scraper that speaks it can watch an appliance without a JSON exporter
// (issue #22 item 3). Written directly rather than through prometheus-cpp: the format is a
// few line rules, and the numbers already exist in the status object; nothing new is
// measured here. docs/outputs.md "Metrics" lists the metrics.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "app/outputs/http_server.hpp"

namespace probeless {

inline constexpr const char* kMetricsContentType = "text/plain; version=0.0.4; charset=utf-8";

enum class MetricType { Gauge, Counter };

// Collects samples by metric family and writes each family's # HELP and # TYPE once, then
// its samples: the format requires a family's lines to be together.
class MetricsText {
 public:
  using Labels = std::vector<std::pair<std::string, std::string>>;

  // `name` matches [a-zA-Z_:][a-zA-Z0-9_:]* and, for a counter, ends in "_total".
  void add(std::string_view name, MetricType type, std::string_view help, const Labels& labels,
           double value);
  std::string text() const;

 private:
  struct Family {
    std::string name, help;
    MetricType type;
    std::vector<std::string> samples;  // "name{labels} value"
  };
  std::vector<Family> families_;
};

// The exposition of a status object as the service builds it (app/pipeline/pipeline.cpp
// Pipeline::status(); what is absent is left out) and of the HTTP server's own counters.
std::string prometheus_text(const nlohmann::json& status, const HttpServerStats& http);

}  // namespace probeless
