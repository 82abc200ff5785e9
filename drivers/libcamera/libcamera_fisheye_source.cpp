#include "drivers/libcamera/libcamera_fisheye_source.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "drivers/libcamera/libcamera_camera.hpp"
#include "drivers/libcamera/libcamera_runtime.hpp"

namespace probeless::libcam {
namespace {

const char* control_note(bool offered) {
  return offered ? "per request" : "not offered (frames keep the requested value)";
}

}  // namespace

LibcameraFisheyeSource::LibcameraFisheyeSource(LibcameraOptions options)
    : options_(std::move(options)) {
  if (!try_open())
    spdlog::warn("{}: {}; will retry every {} ms", name(), last_error(), options_.reopen_ms);
}

LibcameraFisheyeSource::~LibcameraFisheyeSource() {
  camera_.reset();  // before the manager it needs
}

std::string LibcameraFisheyeSource::name() const {
  return "libcamera:" + options_.camera_id;
}

const StreamInfo* LibcameraFisheyeSource::stream_info() const {
  return camera_ ? &camera_->info() : nullptr;
}

std::string LibcameraFisheyeSource::last_error() const {
  return error_.get();
}

void LibcameraFisheyeSource::set_next_exposure(const ExposureStamp& exposure) {
  std::lock_guard lock(mutex_);
  requested_ = exposure;
}

// No device (a failed look or a lost one): say why, and look again reopen_ms from now.
bool LibcameraFisheyeSource::no_device(const std::string& why) {
  state_ = SourceState::NoDevice;
  error_.set(why);
  reopen_.looked();
  return false;
}

bool LibcameraFisheyeSource::try_open() {
  ExposureStamp initial;
  {
    std::lock_guard lock(mutex_);
    initial = requested_;  // a camera that comes back gets the current exposure again
  }
  try {
    // Kept for the source's life: the manager's hotplug monitor is what sees the camera
    // come back.
    if (!manager_) manager_ = shared_camera_manager();
    camera_ = std::make_unique<LibcameraCamera>(manager_, options_, initial);
  } catch (const ConfigError& e) {
    // At start-up a wrong size or format is the configuration's fault: say so at once. Once
    // running, the camera that came back may be another one: keep waiting for the right one.
    if (sequence_ == 0) throw;
    return no_device(e.what());
  } catch (const std::runtime_error& e) {  // DeviceError, or libcamera failing to start
    return no_device(e.what());
  }
  const StreamInfo& info = camera_->info();
  spdlog::info("{}: camera '{}' {} {}x{}, ExposureTime {}, AnalogueGain {}", name(), info.camera_id,
               info.format, info.width, info.height, control_note(info.exposure_time),
               control_note(info.analogue_gain));
  error_.set({});
  last_frame_ns_ = monotonic_now_ns();
  state_ = SourceState::NoSignal;  // open, no completed request yet
  return true;
}

void LibcameraFisheyeSource::lose_device(const std::string& why) {
  camera_.reset();  // stops, frees and releases: the camera may come back under the same id
  no_device(why);
  spdlog::warn("{}: camera lost ({}); looking for it every {} ms", name(), why, options_.reopen_ms);
}

ReadResult LibcameraFisheyeSource::read(FisheyeFrame& frame, std::chrono::milliseconds timeout) {
  const TimestampNs deadline = monotonic_now_ns() + ms_to_ns(timeout.count());
  if (!camera_ && (!reopen_.wait_until_due(deadline) || !try_open())) return ReadResult::Error;
  ExposureStamp next;
  {
    std::lock_guard lock(mutex_);
    next = requested_;
  }
  bool got = false;
  try {
    const TimestampNs left = std::max<TimestampNs>(0, deadline - monotonic_now_ns());
    got = camera_->next_frame(
        std::chrono::milliseconds(left / 1'000'000), next, [&](const CompletedFrame& c) {
          const StreamInfo& info = camera_->info();
          v4l2::convert_to_linear_rgb16(c.bytes, info.pixel, info.width, info.height, frame.raw);
          frame.timestamp_ns = c.timestamp_ns;
          frame.bit_depth = v4l2::output_bit_depth(info.pixel);
          frame.black_level = 0;
          // The request's own stamp, with what the metadata says was applied.
          frame.exposure = c.queued;
          if (c.exposure_us) frame.exposure.exposure.time_s = *c.exposure_us * 1e-6;
          if (c.analogue_gain)
            frame.exposure.exposure.gain_db =
                gain_db_from_linear(std::max(*c.analogue_gain, 1e-3f));
          frame.truth = nullptr;
          pipeline_sequence_ = c.sequence;
        });
  } catch (const DeviceError& e) {
    lose_device(e.what());
    return ReadResult::Error;
  }
  const TimestampNs now = monotonic_now_ns();
  if (!got) {
    if (now - last_frame_ns_ > ms_to_ns(options_.stall_ms)) state_ = SourceState::Stalled;
    return ReadResult::NoFrameYet;
  }
  frame.sequence = sequence_++;
  last_frame_ns_ = now;
  state_ = SourceState::Streaming;
  return ReadResult::Frame;
}

}  // namespace probeless::libcam
