#include "app/outputs/http_metrics.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <optional>

namespace probeless {
namespace {

// Shortest text that reads back as the same double; the format's spellings otherwise.
std::string number_text(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  std::array<char, 32> text{};
  const auto [end, ec] = std::to_chars(text.data(), text.data() + text.size(), v);
  return ec == std::errc() ? std::string(text.data(), end) : "NaN";
}

// Label values are any UTF-8 with \, " and newline escaped.
std::string escaped(std::string_view value) {
  std::string out;
  out.reserve(value.size());
  for (const char c : value) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '"')
      out += "\\\"";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

// HELP text escapes only \ and newline.
std::string help_text(std::string_view help) {
  std::string out;
  for (const char c : help) out += c == '\\' ? "\\\\" : c == '\n' ? "\\n" : std::string(1, c);
  return out;
}

// A number (or a boolean, as 0/1) at a path of the status object; nullopt when absent.
std::optional<double> number_at(const nlohmann::json& j, std::initializer_list<const char*> path) {
  const nlohmann::json* at = &j;
  for (const char* key : path) {
    if (!at->is_object() || !at->contains(key)) return std::nullopt;
    at = &(*at)[key];
  }
  if (at->is_boolean()) return at->get<bool>() ? 1.0 : 0.0;
  if (at->is_number()) return at->get<double>();
  return std::nullopt;
}

std::optional<std::string> string_at(const nlohmann::json& j, const char* object, const char* key) {
  if (!j.is_object() || !j.contains(object) || !j[object].is_object()) return std::nullopt;
  const nlohmann::json& o = j[object];
  if (!o.contains(key) || !o[key].is_string()) return std::nullopt;
  return o[key].get<std::string>();
}

// drivers/source.cpp to_string(SourceState): every state is exposed, the current one 1,
// so a query can watch for any of them without knowing the current one.
constexpr std::array<const char*, 5> kSourceStates = {"streaming", "no_device", "no_signal",
                                                      "stalled", "ended"};

}  // namespace

void MetricsText::add(std::string_view name, MetricType type, std::string_view help,
                      const Labels& labels, double value) {
  auto family = std::find_if(families_.begin(), families_.end(),
                             [&](const Family& f) { return f.name == name; });
  if (family == families_.end()) {
    families_.push_back({std::string(name), std::string(help), type, {}});
    family = families_.end() - 1;
  }
  std::string sample(name);
  if (!labels.empty()) {
    sample += '{';
    for (std::size_t i = 0; i < labels.size(); ++i) {
      if (i > 0) sample += ',';
      sample += labels[i].first + "=\"" + escaped(labels[i].second) + '"';
    }
    sample += '}';
  }
  family->samples.push_back(sample + ' ' + number_text(value));
}

std::string MetricsText::text() const {
  std::string out;
  for (const Family& f : families_) {
    out += "# HELP " + f.name + ' ' + help_text(f.help) + '\n';
    out += "# TYPE " + f.name + (f.type == MetricType::Counter ? " counter\n" : " gauge\n");
    for (const std::string& s : f.samples) out += s + '\n';
  }
  return out;
}

std::string prometheus_text(const nlohmann::json& status, const HttpServerStats& http) {
  MetricsText m;
  const auto G = MetricType::Gauge;
  const auto C = MetricType::Counter;
  auto put = [&](const char* name, MetricType type, const char* help,
                 std::initializer_list<const char*> path) {
    if (auto v = number_at(status, path)) m.add(name, type, help, {}, *v);
  };
  auto put_state = [&](const char* name, const char* help, const char* object) {
    const std::optional<std::string> state =
        object ? string_at(status, object, "state")
               : (status.contains("state") && status["state"].is_string()
                      ? std::optional(status["state"].get<std::string>())
                      : std::nullopt);
    if (state) m.add(name, G, help, {{"state", *state}}, 1);
  };

  put("probeless_frames_per_second", G, "Composites out of the pipeline per second", {"fps"});
  put("probeless_uptime_seconds", G, "Time since the pipeline started", {"uptime_s"});
  put_state("probeless_service_state", "The pipeline's state (label), always 1", nullptr);
  if (status.contains("stages") && status["stages"].is_object()) {
    for (const auto& [stage, s] : status["stages"].items()) {
      for (const auto& [quantile, key] :
           {std::pair{"0.5", "p50_ms"}, std::pair{"0.99", "p99_ms"}}) {
        if (auto ms = number_at(s, {key}))
          m.add("probeless_stage_duration_seconds", G,
                "A pipeline stage's time per frame at a quantile over its recent frames",
                {{"stage", stage}, {"quantile", quantile}}, *ms / 1000);
      }
    }
  }
  put("probeless_frames_processed_total", C, "RGB-D frames processed", {"frames", "processed"});
  put("probeless_frames_out_total", C, "Composites handed to the outputs", {"frames", "out"});
  put("probeless_rgbd_frames_total", C, "RGB-D frames received", {"frames", "rgbd_in"});
  put("probeless_rgbd_frames_dropped_total", C, "RGB-D frames replaced before processing took them",
      {"frames", "rgbd_dropped"});
  put("probeless_fisheye_frames_total", C, "Fisheye frames received", {"frames", "fisheye_in"});

  if (status.contains("sources") && status["sources"].is_object()) {
    for (const auto& [source, s] : status["sources"].items()) {
      if (!s.is_object() || !s.contains("state") || !s["state"].is_string()) continue;
      const std::string state = s["state"].get<std::string>();
      const char* help = "A source's state (label): 1 for the current one";
      for (const char* known : kSourceStates)
        m.add("probeless_source_state", G, help, {{"source", source}, {"state", known}},
              state == known ? 1 : 0);
      if (std::find(kSourceStates.begin(), kSourceStates.end(), state) == kSourceStates.end())
        m.add("probeless_source_state", G, help, {{"source", source}, {"state", state}}, 1);
      m.add("probeless_source_online", G, "1 while a source is streaming", {{"source", source}},
            state == "streaming" ? 1 : 0);
    }
  }

  put_state("probeless_light_state", "The light capture's state (label), always 1", "light");
  put("probeless_light_frames_total", C, "Fisheye frames the light capture processed",
      {"light", "frames"});
  put("probeless_light_frames_dropped_total", C, "Fisheye frames the light capture dropped",
      {"light", "dropped"});
  put("probeless_light_frames_skipped_total", C,
      "Fisheye frames the light capture passed over at [light] update_hz", {"light", "skipped"});
  put("probeless_light_keyframes", G, "Light keyframes held", {"light", "keyframes"});
  put("probeless_light_keyframes_dropped_total", C, "Light keyframes dropped",
      {"light", "keyframes_dropped"});
  put_state("probeless_tracking_state", "The tracker's state (label), always 1", "tracking");
  put("probeless_tracking_lost_total", C, "Times tracking was lost", {"tracking", "lost_count"});
  put("probeless_tracking_keyframes", G, "Tracking keyframes held", {"tracking", "keyframes"});
  put("probeless_tracking_anchor_found", G, "1 while the world anchor is found",
      {"tracking", "anchor", "found"});
  put("probeless_file_output_frames_total", C, "Frames written to files",
      {"file_output", "written"});
  put("probeless_file_output_frames_dropped_total", C, "Frames the file output dropped",
      {"file_output", "dropped"});
  put("probeless_file_output_written_bytes_total", C, "Bytes written to files",
      {"file_output", "bytes"});

  auto http_counter = [&](const char* name, const char* help, std::uint64_t v) {
    m.add(name, C, help, {}, static_cast<double>(v));
  };
  http_counter("probeless_http_requests_total", "HTTP requests", http.requests);
  http_counter("probeless_http_refused_total", "HTTP requests refused (Host, authentication)",
               http.refused);
  http_counter("probeless_http_accept_failures_total", "accept() failures (out of descriptors)",
               http.accept_failures);
  http_counter("probeless_http_header_timeouts_total",
               "Connections closed for headers not complete in time", http.header_timeouts);
  http_counter("probeless_http_evicted_total",
               "Connections closed waiting for headers to stay within max_connections",
               http.evicted);
  http_counter("probeless_http_slow_streams_dropped_total",
               "Stream clients cut by the stalled-client timeout", http.slow_streams_dropped);
  http_counter("probeless_http_frames_published_total", "Frames published to the HTTP server",
               http.frames_published);
  http_counter("probeless_http_sent_bytes_total", "Bytes handed to the kernel, all responses",
               http.bytes_sent);
  m.add("probeless_http_connections", G, "Open HTTP connections, streams included", {},
        static_cast<double>(http.connections));
  m.add("probeless_http_stream_clients", G, "Stream clients connected", {},
        static_cast<double>(http.stream_clients.size()));
  std::uint64_t drops = 0;
  for (const auto& c : http.stream_clients) drops += c.drops;
  m.add("probeless_http_stream_client_drops", G,
        "Frames the connected stream clients missed, summed (falls when a client leaves)", {},
        static_cast<double>(drops));
  return m.text();
}

}  // namespace probeless
