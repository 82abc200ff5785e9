// The HTTP server's one-shot answers (docs/outputs.md "HTTP"): the snapshot, /status,
// ustreamer's /state and OPTIONS, and /metrics. Streams and the event loop are in
// http_server.cpp.
#include <event2/buffer.h>
#include <event2/http.h>

#include <functional>
#include <string>

#include "app/outputs/http_metrics.hpp"
#include "app/outputs/http_server_impl.hpp"

namespace probeless {

// ustreamer's OPTIONS: 200 with what may be asked, for any listed path; the CORS origin,
// when configured, is added by send_body as on every answer.
void HttpServer::Impl::serve_options(evhttp_request* req) {
  evkeyvalq* out = evhttp_request_get_output_headers(req);
  evhttp_add_header(out, "Allow", kAllowed);
  evhttp_add_header(out, "Access-Control-Allow-Methods", kAllowed);
  evhttp_add_header(out, "Access-Control-Allow-Headers", "Authorization");
  send_text(req, HTTP_OK, "OK", "");
}

// ustreamer's snapshot headers: the capture time and the source's state and size.
void HttpServer::Impl::add_frame_headers(evhttp_request* req) {
  evkeyvalq* out = evhttp_request_get_output_headers(req);
  if (current) {
    evhttp_add_header(out, "X-Timestamp", seconds_text(current_wall_ns).c_str());
    evhttp_add_header(out, "X-Timestamp-Monotonic",
                      seconds_text(current->value.timestamp_ns).c_str());
  } else {
    evhttp_add_header(out, "X-Timestamp", seconds_text(wall_clock_now_ns()).c_str());
  }
  evhttp_add_header(out, "X-UStreamer-Online", source_online() ? "true" : "false");
  const JpegSize size = shown_size();
  evhttp_add_header(out, "X-UStreamer-Width", std::to_string(size.width).c_str());
  evhttp_add_header(out, "X-UStreamer-Height", std::to_string(size.height).c_str());
}

bool HttpServer::Impl::make_placeholder(std::string* problem) {
  if (placeholder) return true;
  try {
    placeholder = placeholder_jpeg(kPlaceholderWidth, kPlaceholderHeight, config.jpeg_quality);
    return true;
  } catch (const std::exception& e) {
    if (problem) *problem = e.what();
    return false;
  }
}

void HttpServer::Impl::serve_snapshot(evhttp_request* req) {
  on_frame();  // take a frame published a moment ago even if its wake-up is still queued
  // Before the first frame ustreamer answers 200 with a blank frame and
  // X-UStreamer-Online: false rather than an error: its clients poll and show what they get.
  std::string problem;
  if (!current && !make_placeholder(&problem)) {
    send_text(req, HTTP_INTERNAL, "Internal Server Error", "placeholder: " + problem + "\n");
    return;
  }
  add_frame_headers(req);
  evbuffer* body = evbuffer_new();
  add_jpeg_reference(body, current ? current->value.jpeg : placeholder);
  send_body(req, HTTP_OK, "OK", "image/jpeg", body);
  evbuffer_free(body);
}

void HttpServer::Impl::send_built(evhttp_request* req, const char* what, const char* content_type,
                                  const std::function<std::string()>& make) {
  std::string text;
  try {
    text = make();
  } catch (const std::exception& e) {
    send_text(req, HTTP_INTERNAL, "Internal Server Error",
              std::string(what) + ": " + e.what() + "\n");
    return;
  }
  evbuffer* buf = evbuffer_new();
  evbuffer_add(buf, text.data(), text.size());
  send_body(req, HTTP_OK, "OK", content_type, buf);
  evbuffer_free(buf);
}

void HttpServer::Impl::serve_state(evhttp_request* req) {
  on_frame();
  send_built(req, "state", "application/json", [&] {
    UstreamerState state;
    state.quality = config.jpeg_quality;
    state.online = source_online();
    state.resolution = shown_size();
    const TimestampNs now = monotonic_now_ns();
    state.queued_fps = published_rate.rate_hz(now);
    state.captured_fps = state.queued_fps;
    // The pipeline's own rate when the service reports one: frames captured and processed,
    // not only those that reached this server.
    if (status) {
      const nlohmann::json s = status();
      if (s.is_object() && s.contains("fps") && s["fps"].is_number())
        state.captured_fps = s["fps"].get<double>();
    }
    for (const auto& c : clients) {
      if (c->request == nullptr) continue;
      state.clients.push_back({c->id, c->sent_rate.rate_hz(now), c->options});
    }
    return to_json(state).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  });
}

void HttpServer::Impl::serve_status(evhttp_request* req) {
  send_built(req, "status", "application/json", [&] {
    nlohmann::json body = status ? status() : nlohmann::json::object();
    if (!body.is_object()) body = nlohmann::json{{"service", std::move(body)}};
    body["http"] = to_json(stats());
    // A device or file name in the status may not be UTF-8: replaced (U+FFFD), since dump()
    // would throw.
    return body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  });
}

// The same numbers as /status, from the same callback, in Prometheus' text format.
void HttpServer::Impl::serve_metrics(evhttp_request* req) {
  send_built(req, "metrics", kMetricsContentType, [&] {
    return prometheus_text(status ? status() : nlohmann::json::object(), stats());
  });
}

}  // namespace probeless
