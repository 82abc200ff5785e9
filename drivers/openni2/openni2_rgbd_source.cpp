#include "drivers/openni2/openni2_rgbd_source.hpp"

#include <OpenNI.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <mutex>
#include <thread>

#include "drivers/usb/usb_hotplug.hpp"

namespace probeless::openni2 {
namespace {

constexpr std::size_t kMaxWaiting = 4;

}  // namespace

// OpenNI calls this on its own thread when a driver reports a device gone (a USB unplug);
// read() acts on the flag.
class Openni2RgbdSource::DisconnectListener final
    : public openni::OpenNI::DeviceDisconnectedListener {
 public:
  explicit DisconnectListener(std::atomic<bool>& lost) : lost_(lost) {
    openni::OpenNI::addDeviceDisconnectedListener(this);
  }
  ~DisconnectListener() override { openni::OpenNI::removeDeviceDisconnectedListener(this); }
  void watch(std::string uri) {
    std::lock_guard lock(mutex_);
    uri_ = std::move(uri);
  }
  void onDeviceDisconnected(const openni::DeviceInfo* info) override {
    std::lock_guard lock(mutex_);
    if (info && !uri_.empty() && uri_ == info->getUri()) lost_ = true;
  }

 private:
  std::atomic<bool>& lost_;
  std::mutex mutex_;
  std::string uri_;
};

Openni2RgbdSource::Openni2RgbdSource(Openni2Options options)
    : options_(std::move(options)), runtime_(OpenniRuntime::acquire()) {
  listener_ = std::make_unique<DisconnectListener>(lost_);
  if (!options_.is_file() && options_.hotplug && !options_.usb_vendors.empty()) {
    // Best effort: without USB access (a container, no usbfs) the periodic look still finds
    // the sensor again, only later.
    try {
      watcher_ = std::make_unique<usb::UsbHotplugWatcher>(
          options_.usb_vendors, [this](usb::HotplugEvent event, const usb::UsbDeviceId& id) {
            if (event == usb::HotplugEvent::Arrived) arrived_ = true;
            spdlog::info("{}: USB {} {}", name(),
                         event == usb::HotplugEvent::Arrived ? "arrived" : "left", describe(id));
          });
    } catch (const usb::UsbError& e) {
      spdlog::warn("{}: no USB hotplug ({}); looking for the sensor every {} ms", name(), e.what(),
                   options_.reopen_ms);
    }
  }
  if (!try_open())
    spdlog::warn("{}: {}; will retry every {} ms", name(), last_error(), options_.reopen_ms);
}

Openni2RgbdSource::~Openni2RgbdSource() {
  watcher_.reset();  // no more callbacks into this object
  camera_.reset();
  listener_.reset();
}

const CameraInfo* Openni2RgbdSource::camera_info() const {
  return camera_ ? &camera_->info() : nullptr;
}

std::string Openni2RgbdSource::name() const {
  return "openni2:" + options_.uri;
}

std::string Openni2RgbdSource::last_error() const {
  return error_.get();
}

// No device (a failed look or a lost one): say why, and look again reopen_ms from now.
bool Openni2RgbdSource::no_device(const std::string& why) {
  state_ = SourceState::NoDevice;
  error_.set(why);
  reopen_.looked();
  return false;
}

bool Openni2RgbdSource::try_open() {
  arrived_ = false;
  lost_ = false;
  try {
    camera_ = std::make_unique<Openni2Camera>(options_, runtime_);
  } catch (const DeviceMissing& e) {
    return no_device(e.what());
  } catch (const OpenniError& e) {
    // At start-up this is the configuration's fault: say so at once. Once running, the
    // device that came back may be another one: keep waiting for the right one.
    if (sequence_ == 0) throw;
    return no_device(e.what());
  }
  const CameraInfo& info = camera_->info();
  listener_->watch(info.uri);
  spdlog::info("{}: '{}' {} ({:04x}:{:04x}) colour {} depth {}, registration {}, sync {}{}", name(),
               info.name, info.vendor, info.usb_vendor, info.usb_product, describe(info.colour),
               describe(info.depth), info.registered ? "on" : "off (not offered)",
               info.synced ? "on" : "off",
               info.is_file ? fmt::format(", {} frames", info.colour_frames) : std::string());
  error_.set({});
  colours_.clear();
  depths_.clear();
  anchored_ = false;
  stall_handled_ = false;
  last_frame_ns_ = monotonic_now_ns();
  last_arrival_ns_ = 0;
  state_ = SourceState::NoSignal;  // open, no frame yet
  return true;
}

void Openni2RgbdSource::lose_device(const std::string& why) {
  camera_.reset();
  listener_->watch({});
  no_device(why);
  spdlog::warn("{}: device lost ({}); looking for it every {} ms{}", name(), why,
               options_.reopen_ms, watcher_ ? " and on USB arrival" : "");
}

void Openni2RgbdSource::on_stall(TimestampNs now) {
  if (now - last_frame_ns_ <= ms_to_ns(options_.stall_ms)) return;
  state_ = SourceState::Stalled;
  const CameraInfo& info = camera_->info();
  if (info.synced) {
    // OpenNI's software frame sync (drivers without it in firmware: Dummy, recordings) can
    // hold back every frame when the two streams' frame indices never line up; we met it in
    // about one run in five with the Dummy device. Pairing by timestamp does not need it.
    // Turning sync off on the open device was not enough: the Dummy device's streams stamp
    // frames by frame index, so once one stream's thread fell behind (the VM tests beside a
    // loaded host: 3 suite runs in 5) no colour and depth stamp met again. Fresh streams
    // start level.
    options_.sync = false;
    reopen_now(fmt::format("no frame for {} ms with depth/colour sync on; reopening with sync off",
                           options_.stall_ms));
    return;
  }
  if (stall_handled_ || info.is_file) return;
  if (now - last_arrival_ns_ <= ms_to_ns(options_.stall_ms)) {
    // Frames arrive but no colour meets a depth: the streams are out of step (more than the
    // queues hold apart). Fresh streams start level.
    reopen_now(fmt::format("frames arrive but no colour and depth met for {} ms; reopening",
                           options_.stall_ms));
    return;
  }
  // Silent. A device without a USB port to reset (the Dummy device, a sensor on another bus)
  // is left to come back: on a loaded host the driver's threads are starved, and reopening
  // then only throws away what they were about to deliver (tried: 20 reopens in 4 minutes
  // beside 8 busy loops, each followed by 2-40 s without a pair).
  if (info.usb_vendor == 0 || !options_.reset_on_stall) return;
  // A USB sensor that stops sending is often wedged in its firmware; a port reset
  // re-enumerates it, and the disconnect/reopen path takes over from there.
  stall_handled_ = true;
  try {
    usb::usb_reset(info.usb_vendor, info.usb_product);
    lose_device("stalled for " + std::to_string(options_.stall_ms) + " ms; USB reset");
  } catch (const usb::UsbError& e) {
    spdlog::warn("{}: stalled, and the USB reset failed: {}", name(), e.what());
  }
}

void Openni2RgbdSource::reopen_now(const std::string& why) {
  spdlog::warn("{}: {}", name(), why);
  camera_.reset();
  listener_->watch({});
  bool open = false;
  try {
    open = try_open();
  } catch (const OpenniError& e) {  // try_open's start-up rule does not apply to a reopen
    open = no_device(e.what());
  }
  if (open)
    stall_handled_ = true;  // until a frame arrives: one reopen per stall, not one per second
  else
    spdlog::warn("{}: reopening failed: {}; looking for it every {} ms", name(), last_error(),
                 options_.reopen_ms);
}

TimestampNs Openni2RgbdSource::to_monotonic(std::uint64_t device_us) {
  const TimestampNs now = monotonic_now_ns();
  const auto device_ns = static_cast<TimestampNs>(device_us) * 1000;
  // Anchor on the first frame, and again when device time jumps back (a recording starting
  // over, a sensor that reset its clock).
  if (!anchored_ || device_us < last_device_us_) {
    clock_offset_ns_ = now - device_ns;
    anchored_ = true;
  }
  last_device_us_ = device_us;
  TimestampNs t = device_ns + clock_offset_ns_;
  // A device clock running fast would stamp frames in the future: pull the anchor back.
  if (t > now) {
    clock_offset_ns_ -= t - now;
    t = now;
  }
  t = std::max(t, last_stamp_ns_ + 1);  // strictly increasing, whatever the device does
  last_stamp_ns_ = t;
  return t;
}

bool Openni2RgbdSource::take_pair(RgbdFrame& frame) {
  const auto pair_us = static_cast<std::int64_t>(options_.pair_ms) * 1000;
  while (!colours_.empty() && !depths_.empty()) {
    const auto gap = static_cast<std::int64_t>(colours_.front().device_us) -
                     static_cast<std::int64_t>(depths_.front().device_us);
    if (std::abs(gap) <= pair_us) {
      frame.timestamp_ns = to_monotonic(colours_.front().device_us);
      frame.colour = std::move(colours_.front().image);
      frame.depth = std::move(depths_.front().image);
      frame.truth = nullptr;
      frame.sequence = sequence_++;
      colours_.pop_front();
      depths_.pop_front();
      return true;
    }
    // Each stream's time only grows: the older front will never meet a partner.
    if (gap < 0)
      colours_.pop_front();
    else
      depths_.pop_front();
  }
  return false;
}

ReadResult Openni2RgbdSource::read(RgbdFrame& frame, std::chrono::milliseconds timeout) {
  const TimestampNs deadline = monotonic_now_ns() + ms_to_ns(timeout.count());
  if (camera_ && lost_) lose_device("OpenNI reported the device disconnected");
  if (!camera_) {
    if (state_ == SourceState::Ended) return ReadResult::EndOfStream;
    // Wait for the next look (or the caller's deadline, or a USB arrival), not spin.
    while (!arrived_ && monotonic_now_ns() < std::min(reopen_.next_ns(), deadline))
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if ((!arrived_ && !reopen_.due()) || !try_open()) return ReadResult::Error;
  }
  while (true) {
    if (camera_->finished()) {
      state_ = SourceState::Ended;
      camera_.reset();
      return ReadResult::EndOfStream;
    }
    const TimestampNs left = deadline - monotonic_now_ns();
    StreamFrame got;
    bool have = false;
    try {
      have = camera_->next(std::chrono::milliseconds(std::max<TimestampNs>(0, left / 1'000'000)),
                           got, incoming_colour_, incoming_depth_);
    } catch (const OpenniError& e) {
      lose_device(e.what());
      return ReadResult::Error;
    }
    const TimestampNs now = monotonic_now_ns();
    if (have) last_arrival_ns_ = now;
    if (!have) {
      if (lost_) {
        lose_device("OpenNI reported the device disconnected");
        return ReadResult::Error;
      }
      on_stall(now);
      return ReadResult::NoFrameYet;
    }
    // A stream whose time went back (a recording starting over) makes everything waiting
    // stale.
    const bool colour = got.kind == StreamKind::Colour;
    const bool went_back = colour ? !colours_.empty() && got.device_us < colours_.back().device_us
                                  : !depths_.empty() && got.device_us < depths_.back().device_us;
    if (went_back) {
      colours_.clear();
      depths_.clear();
    }
    if (colour) {
      colours_.push_back({std::move(incoming_colour_), got.device_us});
      if (colours_.size() > kMaxWaiting) colours_.pop_front();
    } else {
      depths_.push_back({std::move(incoming_depth_), got.device_us});
      if (depths_.size() > kMaxWaiting) depths_.pop_front();
    }
    if (take_pair(frame)) {
      last_frame_ns_ = now;
      stall_handled_ = false;
      state_ = SourceState::Streaming;
      return ReadResult::Frame;
    }
    if (now >= deadline) {
      on_stall(now);
      return ReadResult::NoFrameYet;
    }
  }
}

}  // namespace probeless::openni2
