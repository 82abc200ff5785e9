#include "app/outputs/kms_display.hpp"

#include <spdlog/spdlog.h>

#include <condition_variable>

#include "app/outputs/display/display_mode.hpp"
#include "app/outputs/display/kms_screen.hpp"

namespace probeless {

using namespace std::chrono_literals;

KmsDisplay::KmsDisplay(KmsDisplayConfig config) : config_(std::move(config)) {
  if (!config_.screen.mode.empty()) display::parse_mode_request(config_.screen.mode);
  thread_ = std::jthread([this](std::stop_token stop) { run(stop); });
}

KmsDisplay::~KmsDisplay() {
  stop();
}

void KmsDisplay::submit(std::shared_ptr<const ImageRGB8> frame, TimestampNs capture_ns) {
  if (!frame || frame->empty()) return;
  {
    std::lock_guard lock(mutex_);
    ++stats_.frames_in;
  }
  frames_.publish(Submitted{std::move(frame), capture_ns});
}

void KmsDisplay::stop() {
  if (!thread_.joinable()) return;
  thread_.request_stop();
  frames_.close();
  thread_.join();
}

void KmsDisplay::record_error(const std::string& what) {
  bool changed = false;
  {
    std::lock_guard lock(mutex_);
    stats_.state = "error";
    changed = what != stats_.last_error;
    stats_.last_error = what;
  }
  // Once per distinct reason: a missing monitor stays missing at every retry.
  if (changed)
    spdlog::warn("display: {} (retrying every {} ms)", what, config_.retry_every.count());
}

bool KmsDisplay::open_screen(std::unique_ptr<display::KmsScreen>& screen) {
  try {
    screen = std::make_unique<display::KmsScreen>(config_.screen);
  } catch (const std::exception& e) {  // DisplayError, and std::bad_alloc-like surprises
    record_error(e.what());
    return false;
  }
  std::lock_guard lock(mutex_);
  const auto& t = screen->target();
  stats_.state = "showing";
  stats_.card = t.card.string();
  stats_.driver = t.driver;
  stats_.connector = t.connector;
  stats_.mode = display::to_string(t.mode);
  stats_.renderer = screen->renderer();
  return true;
}

void KmsDisplay::run(std::stop_token stop) {
  std::unique_ptr<display::KmsScreen> screen;  // lives and dies on this thread (EGL context)
  LatestFrame<Submitted>::Sequence seen = 0;
  TimestampNs last_vblank = 0;
  std::mutex wait_mutex;
  std::condition_variable_any retry_wait;
  while (!stop.stop_requested()) {
    if (!screen && !open_screen(screen)) {
      std::unique_lock lock(wait_mutex);
      retry_wait.wait_for(lock, stop, config_.retry_every, [] { return false; });
      continue;
    }
    auto item = frames_.wait_newer(seen, 100ms, stop);
    if (!item) continue;
    seen = item->sequence;
    try {
      const auto result = screen->present(*item->value.image);
      rate_.tick(monotonic_now_ns());
      std::lock_guard lock(mutex_);
      ++stats_.frames_shown;
      if (result.flip) {
        ++stats_.flips;
        if (last_vblank != 0)
          stats_.last_flip_interval_ms =
              static_cast<double>(result.flip->timestamp_ns - last_vblank) * 1e-6;
        last_vblank = result.flip->timestamp_ns;
        if (item->value.capture_ns > 0)
          latency_.record(
              "capture_to_flip",
              static_cast<double>(result.flip->timestamp_ns - item->value.capture_ns) * 1e-6);
      }
    } catch (const std::exception& e) {
      record_error(e.what());
      screen.reset();  // restores the CRTC; the next round reopens from scratch
      last_vblank = 0;
    }
  }
}

KmsDisplayStats KmsDisplay::stats() const {
  std::lock_guard lock(mutex_);
  KmsDisplayStats s = stats_;
  s.dropped = frames_.drops();
  s.flips_per_s = rate_.rate_hz(monotonic_now_ns());
  const auto latency = latency_.summaries();
  if (auto it = latency.find("capture_to_flip"); it != latency.end())
    s.capture_to_flip = it->second;
  return s;
}

nlohmann::json KmsDisplay::status() const {
  const KmsDisplayStats s = stats();
  return {{"state", s.state},
          {"card", s.card},
          {"driver", s.driver},
          {"connector", s.connector},
          {"mode", s.mode},
          {"renderer", s.renderer},
          {"frames_in", s.frames_in},
          {"frames_shown", s.frames_shown},
          {"flips", s.flips},
          {"dropped", s.dropped},
          {"flips_per_s", s.flips_per_s},
          {"last_flip_interval_ms", s.last_flip_interval_ms},
          {"capture_to_flip",
           {{"p50_ms", s.capture_to_flip.p50_ms}, {"p99_ms", s.capture_to_flip.p99_ms}}},
          {"last_error", s.last_error}};
}

}  // namespace probeless
