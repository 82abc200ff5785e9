#pragma once
// The tethered display as a pipeline output (docs/display.md, app/outputs/output.hpp): the
// composite shown full screen on a KMS connector, EGL on GBM, no display server. Like the
// other outputs it never slows the pipeline: submit() replaces the newest frame in a
// LatestFrame slot and returns, and the display's own thread draws, flips and waits for
// vblank, skipping frames it had no time for. A screen that cannot be opened (no card yet,
// connector unplugged, another DRM master) is retried every `retry_every`, with the reason
// in status() and logged once.
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "app/outputs/display/kms_screen_config.hpp"
#include "app/outputs/output.hpp"
#include "base/latest_frame.hpp"
#include "base/stage_stats.hpp"
#include "core/image.hpp"

namespace probeless {
namespace display {
class KmsScreen;
}

// [display] of the service config (docs/configuration.md).
struct KmsDisplayConfig {
  // The service's: off by default, a service that grabs the console's screen must be asked
  // to. The display itself ignores it.
  bool enabled = false;
  display::KmsScreenConfig screen;
  std::chrono::milliseconds retry_every{2000};
};

struct KmsDisplayStats {
  std::string state = "opening";                        // "opening", "showing", "error" (retrying)
  std::string card, driver, connector, mode, renderer;  // of the screen last opened
  std::uint64_t frames_in = 0;
  std::uint64_t frames_shown = 0;  // mode sets plus flips
  std::uint64_t flips = 0;         // completed page flips (vblank events)
  std::uint64_t dropped = 0;       // replaced before the display thread took them
  double flips_per_s = 0;
  double last_flip_interval_ms = 0;  // between the last two vblank timestamps
  // A frame's capture time (CLOCK_MONOTONIC) to the vblank event of the flip that showed it,
  // over the last 300 flips (none: 0): the display path's share of glass-to-glass latency,
  // reported as `bench latency` reports the streams' (docs/outputs.md). NO SIGNAL repeats,
  // which carry an old capture time, are not counted.
  TimingSummary capture_to_flip;
  std::string last_error;
};

class KmsDisplay final : public Output {
 public:
  // Checks the mode string at once (DisplayError), then opens the screen on its thread.
  explicit KmsDisplay(KmsDisplayConfig config);
  ~KmsDisplay() override;
  KmsDisplay(const KmsDisplay&) = delete;
  KmsDisplay& operator=(const KmsDisplay&) = delete;

  // `capture_ns`: the frame's capture time for capture_to_flip; 0 leaves the frame out of it.
  void submit(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns = 0);
  // Joins the thread; the screen's destructor puts the previous CRTC back. Idempotent.
  void stop() override;

  KmsDisplayStats stats() const;
  nlohmann::json status() const;  // stats() for /status

  // Output: NO SIGNAL frames too, the screen shows the fault.
  std::string_view name() const override { return "display"; }
  OutputNeeds needs() const override { return {.colour = true}; }
  void offer(const OutputFrame& frame) override {
    submit(frame.colour, frame.no_signal ? 0 : frame.timestamp_ns);
  }
  void add_status(nlohmann::json& j) const override { j["display"] = status(); }

 private:
  void run(std::stop_token stop);
  bool open_screen(std::unique_ptr<display::KmsScreen>& screen);
  void record_error(const std::string& what);

  KmsDisplayConfig config_;
  struct Submitted {
    std::shared_ptr<const ImageRGB8> image;
    TimestampNs capture_ns = 0;
  };
  LatestFrame<Submitted> frames_;
  StageStats latency_;  // "capture_to_flip"
  RateMeter rate_;
  mutable std::mutex mutex_;
  KmsDisplayStats stats_;
  std::jthread thread_;
};

}  // namespace probeless
