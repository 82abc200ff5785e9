#include "drivers/openni2/openni2_camera.hpp"

#include <OpenNI.h>

#include <algorithm>
#include <cstring>
#include <deque>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

namespace probeless::openni2 {

struct Openni2Camera::Handles {
  // Declaration order is teardown order reversed: streams go before the device.
  openni::Device device;
  openni::VideoStream colour;
  openni::VideoStream depth;
};

namespace {

// Between stopping and destroying a recording's streams: see close().
constexpr auto kStopGrace = std::chrono::milliseconds(80);

// The Dummy driver's streams (OpenNI2's DummyDevice, class OzStream) each run a thread that is
// never joined: stop() only clears a flag the thread reads every 33 ms, and a thread that
// starts late sets it again. Destroying a stream frees what that thread still reads. An 80 ms
// grace after stop() covered an idle host but not a starved one: `probeless run` in the VM
// beside a loaded host (TCG) died of SIGSEGV once in about a dozen board checks, after the
// source reopened the device at start-up. So a closed Dummy device is parked, streams, device
// and runtime together, and destroyed only after kParkFor (300 of the driver's periods), at a
// later close. What is parked at exit is left to the process's end, so OpenNI is never shut
// down (its drivers unloaded) under a thread of theirs that may still run.
constexpr auto kParkFor = std::chrono::seconds(10);

class ParkedDummies {
 public:
  static ParkedDummies& instance() {
    static auto* parked = new ParkedDummies;  // never destroyed: see kParkFor
    return *parked;
  }
  // `handles` keeps the runtime's reference beside it, and goes before it.
  void park(std::shared_ptr<OpenniRuntime> runtime, std::shared_ptr<void> handles) {
    const auto now = std::chrono::steady_clock::now();
    std::vector<Entry> due;
    {
      std::lock_guard lock(mutex_);
      while (!parked_.empty() && now - parked_.front().since >= kParkFor) {
        due.push_back(std::move(parked_.front()));
        parked_.pop_front();
      }
      parked_.push_back({now, std::move(runtime), std::move(handles)});
    }
  }  // `due` destroyed here, outside the lock
  std::size_t size() const {
    std::lock_guard lock(mutex_);
    return parked_.size();
  }

 private:
  struct Entry {
    std::chrono::steady_clock::time_point since;
    std::shared_ptr<OpenniRuntime> runtime;  // declared first: outlives the handles
    std::shared_ptr<void> handles;
  };
  mutable std::mutex mutex_;
  std::deque<Entry> parked_;
};

bool is_dummy_uri(const std::string& uri) {
  return uri == "Dummy" || uri == "Oz" || uri == "PingPong";
}

VideoModeInfo mode_info(const openni::VideoMode& m, const char* sensor) {
  return {sensor, m.getResolutionX(), m.getResolutionY(), m.getFps(),
          pixel_format_name(m.getPixelFormat())};
}

std::string offered(const openni::SensorInfo& sensor, const char* label) {
  std::string text;
  const auto& modes = sensor.getSupportedVideoModes();
  for (int i = 0; i < modes.getSize(); ++i)
    text += (text.empty() ? "" : ", ") + describe(mode_info(modes[i], label));
  return text.empty() ? "none" : text;
}

// The supported mode of the requested size and rate in the first usable pixel format.
const openni::VideoMode* pick_mode(const openni::SensorInfo& sensor, int width, int height, int fps,
                                   std::initializer_list<openni::PixelFormat> formats) {
  const auto& modes = sensor.getSupportedVideoModes();
  for (openni::PixelFormat format : formats) {
    for (int i = 0; i < modes.getSize(); ++i) {
      const openni::VideoMode& m = modes[i];
      if (m.getResolutionX() == width && m.getResolutionY() == height && m.getFps() == fps &&
          m.getPixelFormat() == format)
        return &m;
    }
  }
  return nullptr;
}

bool same_mode(const openni::VideoMode& a, const openni::VideoMode& b) {
  return a.getResolutionX() == b.getResolutionX() && a.getResolutionY() == b.getResolutionY() &&
         a.getFps() == b.getFps() && a.getPixelFormat() == b.getPixelFormat();
}

}  // namespace

Openni2Camera::Openni2Camera(const Openni2Options& options, std::shared_ptr<OpenniRuntime> runtime)
    : runtime_(std::move(runtime)), handles_(std::make_unique<Handles>()), repeat_(options.repeat) {
  info_.is_file = options.is_file();
  const std::string what = info_.is_file         ? "recording '" + options.uri + "'"
                           : options.uri.empty() ? std::string("the first OpenNI2 device")
                                                 : "OpenNI2 device '" + options.uri + "'";
  if (info_.is_file && !std::filesystem::is_regular_file(options.uri))
    throw OpenniError(what + " does not exist");
  const char* uri = options.uri.empty() ? openni::ANY_DEVICE : options.uri.c_str();
  if (handles_->device.open(uri) != openni::STATUS_OK) {
    const std::string why = "cannot open " + what + ": " + openni_error_text();
    // A recording that is there but does not open is corrupt: waiting will not help.
    if (info_.is_file) throw OpenniError(why);
    throw DeviceMissing(why);
  }
  const openni::DeviceInfo& d = handles_->device.getDeviceInfo();
  info_.uri = d.getUri();
  info_.vendor = d.getVendor();
  info_.name = d.getName();
  info_.usb_vendor = static_cast<std::uint16_t>(d.getUsbVendorId());
  info_.usb_product = static_cast<std::uint16_t>(d.getUsbProductId());
  if (info_.is_file) {
    openni::PlaybackControl* playback = handles_->device.getPlaybackControl();
    if (!playback) throw OpenniError(what + " opened without playback control");
    // OpenNI's own speed 0 ("fastest") overwrites frames the reader has not taken yet;
    // its manual mode (-1) hands out every frame as fast as they are read.
    playback->setSpeed(options.speed > 0 ? static_cast<float>(options.speed) : -1.0f);
    playback->setRepeatEnabled(options.repeat);
  }
  try {
    configure_streams(options);
  } catch (...) {
    close();
    throw;
  }
}

void Openni2Camera::configure_streams(const Openni2Options& options) {
  openni::Device& device = handles_->device;
  const std::string who = "OpenNI2 device '" + info_.uri + "'";
  struct Wanted {
    openni::SensorType type;
    const char* label;
    openni::VideoStream& stream;
    std::initializer_list<openni::PixelFormat> formats;
    VideoModeInfo& info;
  };
  Wanted wanted[] = {{openni::SENSOR_COLOR,
                      "colour",
                      handles_->colour,
                      {openni::PIXEL_FORMAT_RGB888},
                      info_.colour},
                     {openni::SENSOR_DEPTH,
                      "depth",
                      handles_->depth,
                      {openni::PIXEL_FORMAT_DEPTH_1_MM, openni::PIXEL_FORMAT_DEPTH_100_UM},
                      info_.depth}};
  for (Wanted& w : wanted) {
    const openni::SensorInfo* sensor = device.getSensorInfo(w.type);
    if (!sensor) throw OpenniError(who + " has no " + w.label + " stream");
    if (w.stream.create(device, w.type) != openni::STATUS_OK)
      throw OpenniError(who + ": cannot create the " + w.label + " stream: " + openni_error_text());
    if (!info_.is_file) {
      // A recording plays the mode it was made in; a device is asked for the configured one.
      const openni::VideoMode* mode =
          pick_mode(*sensor, options.width, options.height, options.fps, w.formats);
      if (!mode) {
        throw OpenniError(who + " has no " + w.label + " mode " + std::to_string(options.width) +
                          "x" + std::to_string(options.height) + "@" + std::to_string(options.fps) +
                          " in a usable format; it offers: " + offered(*sensor, w.label));
      }
      // Only set what differs: some drivers (Dummy) refuse setVideoMode even for their one
      // mode.
      if (!same_mode(w.stream.getVideoMode(), *mode) &&
          w.stream.setVideoMode(*mode) != openni::STATUS_OK) {
        throw OpenniError(who + " refused the " + w.label + " mode " +
                          describe(mode_info(*mode, w.label)) + ": " + openni_error_text());
      }
    }
    w.info = mode_info(w.stream.getVideoMode(), w.label);
    if (w.info.pixel_format != "RGB888" && w.info.pixel_format != "DEPTH_1_MM" &&
        w.info.pixel_format != "DEPTH_100_UM") {
      throw OpenniError(who + ": the " + std::string(w.label) + " stream is " + describe(w.info) +
                        "; probeless reads RGB888 colour and mm depth");
    }
  }
  if (info_.colour.width != info_.depth.width || info_.colour.height != info_.depth.height) {
    throw OpenniError(who + ": colour " + describe(info_.colour) + " and depth " +
                      describe(info_.depth) + " differ in size; an RGB-D frame needs one size");
  }
  info_.colour_hfov_rad = handles_->colour.getHorizontalFieldOfView();
  info_.colour_vfov_rad = handles_->colour.getVerticalFieldOfView();
  if (info_.is_file) {
    openni::PlaybackControl* playback = device.getPlaybackControl();
    info_.colour_frames = playback->getNumberOfFrames(handles_->colour);
    info_.depth_frames = playback->getNumberOfFrames(handles_->depth);
    // A recording carries whatever registration it was made with.
    info_.registered =
        device.getImageRegistrationMode() == openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR;
  } else if (options.registration &&
             device.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR)) {
    info_.registered = device.setImageRegistrationMode(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR) ==
                       openni::STATUS_OK;
  }
  // Not for recordings: their frames are already what they are, and OpenNI's software sync
  // (matching frame indices) dropped about half the pairs of a manual-speed playback.
  if (options.sync && !info_.is_file)
    info_.synced = device.setDepthColorSyncEnabled(true) == openni::STATUS_OK;
  if (handles_->depth.start() != openni::STATUS_OK || handles_->colour.start() != openni::STATUS_OK)
    throw OpenniError(who + ": cannot start streaming: " + openni_error_text());
}

Openni2Camera::~Openni2Camera() {
  close();
}

void Openni2Camera::close() {
  if (info_.is_file) {
    // libOniFile's player thread walks its stream list without the lock that destroying a
    // stream takes (a crash in about one teardown in ten here). In manual mode it parks in
    // a locked wait for the next read; with the streams stopped it only looks every 10 ms.
    if (openni::PlaybackControl* playback = handles_->device.getPlaybackControl())
      playback->setSpeed(-1.0f);
  }
  if (!handles_) return;  // parked by an earlier close()
  handles_->colour.stop();
  handles_->depth.stop();
  if (is_dummy_uri(info_.uri)) {
    ParkedDummies::instance().park(runtime_, std::shared_ptr<Handles>(std::move(handles_)));
    return;
  }
  if (info_.is_file) std::this_thread::sleep_for(kStopGrace);
  handles_->colour.destroy();
  handles_->depth.destroy();
  handles_->device.close();
}

std::size_t parked_dummy_devices() {
  return ParkedDummies::instance().size();
}

void Openni2Camera::disable_sync() {
  handles_->device.setDepthColorSyncEnabled(false);
  info_.synced = false;
}

bool Openni2Camera::finished() const {
  if (!info_.is_file || repeat_) return false;
  return last_colour_index_ >= info_.colour_frames && last_depth_index_ >= info_.depth_frames;
}

bool Openni2Camera::next(std::chrono::milliseconds timeout, StreamFrame& out, ImageRGB8& colour,
                         DepthImage& depth) {
  openni::VideoStream* streams[] = {&handles_->colour, &handles_->depth};
  int ready = -1;
  const int wait_ms = static_cast<int>(std::max<std::int64_t>(0, timeout.count()));
  const openni::Status waited = openni::OpenNI::waitForAnyStream(streams, 2, &ready, wait_ms);
  if (waited == openni::STATUS_TIME_OUT) return false;
  if (waited != openni::STATUS_OK || ready < 0)
    throw OpenniError("waiting for frames failed: " + openni_error_text());
  openni::VideoFrameRef frame;
  if (streams[ready]->readFrame(&frame) != openni::STATUS_OK || !frame.isValid())
    throw OpenniError("reading a frame failed: " + openni_error_text());
  const int width = frame.getWidth(), height = frame.getHeight();
  const auto* bytes = static_cast<const std::uint8_t*>(frame.getData());
  const int stride = frame.getStrideInBytes();
  if (ready == 0) {
    // empty(): a buffer the source moved out keeps its size but not its pixels.
    if (colour.empty() || colour.width() != width || colour.height() != height)
      colour = ImageRGB8(width, height);
    for (int y = 0; y < height; ++y)
      std::memcpy(colour.row(y), bytes + static_cast<std::size_t>(y) * stride,
                  colour.row_elements());
    out.kind = StreamKind::Colour;
    last_colour_index_ = frame.getFrameIndex();
  } else {
    if (depth.empty() || depth.width() != width || depth.height() != height)
      depth = DepthImage(width, height);
    const bool tenths = frame.getVideoMode().getPixelFormat() == openni::PIXEL_FORMAT_DEPTH_100_UM;
    for (int y = 0; y < height; ++y) {
      const auto* src =
          reinterpret_cast<const std::uint16_t*>(bytes + static_cast<std::size_t>(y) * stride);
      std::uint16_t* dst = depth.row(y);
      if (tenths) {
        for (int x = 0; x < width; ++x) dst[x] = static_cast<std::uint16_t>((src[x] + 5) / 10);
      } else {
        std::memcpy(dst, src, static_cast<std::size_t>(width) * sizeof(std::uint16_t));
      }
    }
    out.kind = StreamKind::Depth;
    last_depth_index_ = frame.getFrameIndex();
  }
  out.device_us = frame.getTimestamp();
  out.index = frame.getFrameIndex();
  return true;
}

}  // namespace probeless::openni2
