#include "drivers/v4l2/v4l2_fisheye_source.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "drivers/v4l2/v4l2_camera.hpp"

namespace probeless::v4l2 {
namespace {

constexpr double kExposureUnitS = 100e-6;  // V4L2_CID_EXPOSURE_ABSOLUTE counts 100 us
constexpr std::size_t kHistory = 32;       // control changes kept for stamping late frames

}  // namespace

V4l2FisheyeSource::V4l2FisheyeSource(V4l2Options options) : options_(std::move(options)) {
  if (!try_open())
    spdlog::warn("{}: {}; will retry every {} ms", name(), last_error(), options_.reopen_ms);
}

V4l2FisheyeSource::~V4l2FisheyeSource() = default;

const CaptureInfo* V4l2FisheyeSource::capture_info() const {
  return camera_ ? &camera_->info() : nullptr;
}

std::string V4l2FisheyeSource::last_error() const {
  return error_.get();
}

void V4l2FisheyeSource::set_next_exposure(const ExposureStamp& exposure) {
  std::lock_guard lock(mutex_);
  pending_ = exposure;
  requested_ = exposure;
}

// No device (a failed look or a lost one): say why, and look again reopen_ms from now.
bool V4l2FisheyeSource::no_device(const std::string& why) {
  state_ = SourceState::NoDevice;
  error_.set(why);
  reopen_.looked();
  return false;
}

bool V4l2FisheyeSource::try_open() {
  try {
    camera_ = std::make_unique<V4l2Camera>(options_);
  } catch (const DeviceError& e) {
    return no_device(e.what());
  } catch (const ConfigError& e) {
    // At start-up a wrong size or format is the configuration's fault: say so at once. Once
    // running, the device that came back may be another one: keep waiting for the right one.
    if (sequence_ == 0 && applied_.empty()) throw;
    return no_device(e.what());
  }
  const CaptureInfo& info = camera_->info();
  spdlog::info("{}: {} '{}' ({}) {} {}x{} at {:.2f} fps, exposure control {}, gain control {}",
               name(), info.path, info.card, info.driver, info.fourcc, info.width, info.height,
               info.fps, info.exposure.present ? "yes" : "no", info.gain.present ? "yes" : "no");
  error_.set({});
  last_frame_ns_ = monotonic_now_ns();
  state_ = SourceState::NoSignal;  // open, no frame yet
  {
    std::lock_guard lock(mutex_);
    pending_ = requested_;  // a device that comes back gets the current exposure again
  }
  return true;
}

void V4l2FisheyeSource::lose_device(const std::string& why) {
  camera_.reset();  // stops streaming, unmaps, closes: the node may come back as a new one
  no_device(why);
  spdlog::warn("{}: device lost ({}); looking for it every {} ms", name(), why, options_.reopen_ms);
}

void V4l2FisheyeSource::apply_pending_exposure() {
  std::optional<ExposureStamp> want;
  {
    std::lock_guard lock(mutex_);
    want.swap(pending_);
  }
  if (!want) return;
  const CaptureInfo& info = camera_->info();
  const double unity = static_cast<double>(
      options_.unity_gain > 0 ? options_.unity_gain : std::max<std::int64_t>(1, info.gain.def));
  const auto exposure_raw = std::llround(want->exposure.time_s / kExposureUnitS);
  // At least 1: a zero gain is a black frame, and its dB is -infinity.
  const auto gain_raw = std::max<long long>(1, std::llround(unity * want->exposure.gain()));
  const AppliedControls applied = camera_->set_controls(exposure_raw, gain_raw);
  // Controls the device lacks keep the requested value: the frame cannot say otherwise
  // (docs/drivers.md "Controls").
  ExposureStamp stamp = *want;
  if (applied.exposure)
    stamp.exposure.time_s = static_cast<double>(*applied.exposure) * kExposureUnitS;
  if (applied.gain)
    stamp.exposure.gain_db = gain_db_from_linear(std::max<double>(*applied.gain, 1e-3) / unity);
  applied_.push_back({monotonic_now_ns(), stamp});
  while (applied_.size() > kHistory) applied_.pop_front();
}

ExposureStamp V4l2FisheyeSource::stamp_for(TimestampNs frame_ns) const {
  // The newest change made at least `latency` frame periods before the frame's timestamp; a
  // frame older than every change in the history took the oldest one kept.
  const double fps = camera_ ? camera_->info().fps : options_.fps;
  const auto latency = static_cast<TimestampNs>(options_.latency_frames * 1e9 / fps);
  for (auto it = applied_.rbegin(); it != applied_.rend(); ++it) {
    if (it->at_ns + latency <= frame_ns) return it->stamp;
  }
  return applied_.empty() ? ExposureStamp{} : applied_.front().stamp;
}

ReadResult V4l2FisheyeSource::read(FisheyeFrame& frame, std::chrono::milliseconds timeout) {
  const TimestampNs deadline = monotonic_now_ns() + ms_to_ns(timeout.count());
  if (!camera_ && (!reopen_.wait_until_due(deadline) || !try_open())) return ReadResult::Error;
  bool got = false;
  try {
    apply_pending_exposure();
    const TimestampNs left = std::max<TimestampNs>(0, deadline - monotonic_now_ns());
    got = camera_->next_frame(
        std::chrono::milliseconds(left / 1'000'000),
        [&](std::span<const std::uint8_t> bytes, TimestampNs t, std::uint32_t driver_sequence) {
          const CaptureInfo& info = camera_->info();
          convert_to_linear_rgb16(bytes, info.pixel, info.width, info.height, frame.raw);
          frame.timestamp_ns = t;
          frame.bit_depth = output_bit_depth(info.pixel);
          frame.black_level = 0;
          frame.exposure = stamp_for(t);
          frame.truth = nullptr;
          driver_sequence_ = driver_sequence;
        });
  } catch (const DeviceError& e) {
    lose_device(e.what());
    return ReadResult::Error;
  }
  const TimestampNs now = monotonic_now_ns();
  if (!got) {
    // Stalled: open but silent for five frame periods (at least a second).
    const auto stall =
        std::max<TimestampNs>(1'000'000'000, static_cast<TimestampNs>(5e9 / camera_->info().fps));
    if (now - last_frame_ns_ > stall) state_ = SourceState::Stalled;
    return ReadResult::NoFrameYet;
  }
  frame.sequence = sequence_++;
  last_frame_ns_ = now;
  state_ = SourceState::Streaming;
  return ReadResult::Frame;
}

}  // namespace probeless::v4l2
