#pragma once
// The fisheye on a V4L2 capture device (docs/drivers.md "V4L2 fisheye"): mmap streaming,
// driver timestamps, manual exposure and gain from set_next_exposure(), frames converted to
// linear raw RGB16 and stamped with the exposure read back from the device. A device that
// disappears (ENODEV, EIO: unplug, driver unbind) makes the state "no device"; read() then
// looks for it again every reopen_ms and streams again once it is back.
#include <atomic>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "drivers/device_health.hpp"
#include "drivers/source.hpp"
#include "drivers/v4l2/v4l2_options.hpp"

namespace probeless::v4l2 {

class V4l2Camera;
struct CaptureInfo;

class V4l2FisheyeSource final : public FisheyeSource {
 public:
  // Opens the device now if it is there; a missing device is state "no device", not an
  // error. Throws ConfigError (v4l2_camera.hpp) when the device cannot give the configured
  // size or format: waiting would not fix that.
  explicit V4l2FisheyeSource(V4l2Options options);
  ~V4l2FisheyeSource() override;

  ReadResult read(FisheyeFrame& frame, std::chrono::milliseconds timeout) override;
  SourceState state() const override { return state_.load(); }
  std::string last_error() const override;
  std::string name() const override { return "v4l2:" + options_.device; }
  void set_next_exposure(const ExposureStamp& exposure) override;

  // What was negotiated with the device now open (nothing while there is none). For the
  // reader's thread, like read().
  const CaptureInfo* capture_info() const;
  // The driver's sequence number of the last frame read: it counts the frames the driver
  // dropped too, so gaps in it are frames lost before they reached us.
  std::uint32_t driver_sequence() const { return driver_sequence_; }

 private:
  struct Applied {
    TimestampNs at_ns;
    ExposureStamp stamp;
  };
  bool try_open();
  bool no_device(const std::string& why);  // false, for try_open
  void lose_device(const std::string& why);
  void apply_pending_exposure();
  ExposureStamp stamp_for(TimestampNs frame_ns) const;

  V4l2Options options_;
  std::unique_ptr<V4l2Camera> camera_;
  ReopenClock reopen_{options_.reopen_ms};
  TimestampNs last_frame_ns_ = 0;  // monotonic, for "stalled"
  std::uint64_t sequence_ = 0;
  std::uint32_t driver_sequence_ = 0;
  std::deque<Applied> applied_;  // recent control changes, oldest first

  mutable std::mutex mutex_;  // guards pending_ and requested_ (set from other threads)
  std::optional<ExposureStamp> pending_;
  ExposureStamp requested_;
  SharedMessage error_;
  std::atomic<SourceState> state_{SourceState::NoDevice};
};

}  // namespace probeless::v4l2
