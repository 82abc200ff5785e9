#pragma once
// What every output of the service has in common (docs/outputs.md): the pipeline's output
// thread hands each composite to every output through offer(), one loop for all of them.
// An output says what it needs of a frame, so that work nobody asked for is not done: the
// JPEG, above all, is encoded once per frame and only when some output wants it.
//
// offer() never blocks: each output keeps the newest frame (or a short queue) for its own
// thread, and a consumer that does not keep up drops frames, counted in its part of
// /status, instead of slowing the pipeline or the other outputs.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/image.hpp"
#include "core/time.hpp"

namespace probeless {

class HeartbeatRegistry;

struct OutputNeeds {
  bool jpeg = false;
  int jpeg_quality = 80;  // with jpeg; one encode per frame takes the best quality asked
  bool colour = false;    // the composite as RGB
  bool matte = false;     // the occlusion matte (the processing thread then downloads it)
};

// One composite as the outputs get it; what no output needs is left empty.
struct OutputFrame {
  TimestampNs timestamp_ns = 0;  // the RGB-D frame's capture time (CLOCK_MONOTONIC)
  std::shared_ptr<const ImageRGB8> colour;
  std::shared_ptr<const std::vector<std::uint8_t>> jpeg;
  std::shared_ptr<const ImageF> matte;
  // A repeat of the last good frame with the NO SIGNAL banner: `timestamp_ns` is still the
  // last good frame's.
  bool no_signal = false;
};

class Output {
 public:
  virtual ~Output() = default;
  virtual std::string_view name() const = 0;  // as in the factory: "http", "rtsp", ...
  virtual OutputNeeds needs() const = 0;
  // Any thread; returns at once (see the top of this file).
  virtual void offer(const OutputFrame& frame) = 0;
  // Adds this output's part of /status, if it has one.
  virtual void add_status(nlohmann::json& /*status*/) const {}
  // Where a viewer reaches it ("http://...", "rtsp://..."); empty for outputs not served.
  virtual std::string url() const { return {}; }
  // An output with an event loop of its own registers it with the service watchdog
  // (app/service/heartbeat.hpp) and beats from a timer in that loop. Once, after start.
  virtual void watch(HeartbeatRegistry& /*heartbeats*/) {}
  // Drains or drops what is queued and joins the output's thread. Idempotent.
  virtual void stop() = 0;
};

}  // namespace probeless
