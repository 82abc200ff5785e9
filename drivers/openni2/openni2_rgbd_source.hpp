#pragma once
// The RGB-D camera through OpenNI2 (docs/drivers.md "OpenNI2 RGB-D"): a PrimeSense, Xtion,
// Kinect or Orbbec sensor, or an .oni recording. Colour and depth arrive as separate OpenNI
// frames; read() pairs them by device timestamp and hands out RGB-D frames with depth in mm,
// registered to colour where the device can. States: streaming; no signal (open, nothing
// yet); stalled (open, silent for stall_ms); no device (OpenNI reported it disconnected, or
// it is not there: looked for every reopen_ms, at once on a USB replug); ended (a recording
// without repeat has played out).
#include <atomic>
#include <deque>
#include <memory>
#include <string>

#include "drivers/device_health.hpp"
#include "drivers/openni2/openni2_camera.hpp"
#include "drivers/openni2/openni2_options.hpp"
#include "drivers/source.hpp"

namespace probeless::usb {
class UsbHotplugWatcher;
}

namespace probeless::openni2 {

class Openni2RgbdSource final : public RgbdSource {
 public:
  // Opens the device now if it is there; a missing device is state "no device", not an
  // error. Throws OpenniError for what waiting would not fix: a missing or corrupt
  // recording, a device without the configured modes.
  explicit Openni2RgbdSource(Openni2Options options);
  ~Openni2RgbdSource() override;

  ReadResult read(RgbdFrame& frame, std::chrono::milliseconds timeout) override;
  SourceState state() const override { return state_.load(); }
  std::string last_error() const override;
  std::string name() const override;

  // What is open now (nothing while there is no device). For the reader's thread.
  const CameraInfo* camera_info() const;
  // From any thread: the sensor may be back (a USB arrival); look for it at the next read.
  void device_arrived() { arrived_ = true; }
  bool watching_usb() const { return watcher_ != nullptr; }

 private:
  class DisconnectListener;
  bool try_open();
  bool no_device(const std::string& why);  // false, for try_open
  void lose_device(const std::string& why);
  void on_stall(TimestampNs now);
  void reopen_now(const std::string& why);  // a stall's remedy: fresh streams at once
  TimestampNs to_monotonic(std::uint64_t device_us);

  Openni2Options options_;
  std::shared_ptr<OpenniRuntime> runtime_;
  std::unique_ptr<DisconnectListener> listener_;
  std::unique_ptr<usb::UsbHotplugWatcher> watcher_;
  std::unique_ptr<Openni2Camera> camera_;

  // Frames waiting for a partner, oldest first. A few per stream: a recording or a device
  // without sync can deliver two depth frames before the colour frame of the first.
  template <typename ImageT>
  struct Waiting {
    ImageT image;
    std::uint64_t device_us = 0;
  };
  std::deque<Waiting<ImageRGB8>> colours_;
  std::deque<Waiting<DepthImage>> depths_;
  ImageRGB8 incoming_colour_;
  DepthImage incoming_depth_;
  bool take_pair(RgbdFrame& frame);

  ReopenClock reopen_{options_.reopen_ms};
  TimestampNs last_frame_ns_ = 0;    // monotonic, for "stalled"
  TimestampNs last_arrival_ns_ = 0;  // the last frame of either stream, paired or not
  bool stall_handled_ = false;
  std::uint64_t sequence_ = 0;
  // Device time -> CLOCK_MONOTONIC: anchored at the first frame after an open.
  bool anchored_ = false;
  TimestampNs clock_offset_ns_ = 0;
  std::uint64_t last_device_us_ = 0;
  TimestampNs last_stamp_ns_ = 0;

  std::atomic<bool> lost_{false};
  std::atomic<bool> arrived_{false};
  SharedMessage error_;
  std::atomic<SourceState> state_{SourceState::NoDevice};
};

}  // namespace probeless::openni2
