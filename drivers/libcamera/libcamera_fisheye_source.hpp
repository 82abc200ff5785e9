#pragma once
// The fisheye on a libcamera camera (docs/drivers.md "libcamera fisheye"): a CSI sensor
// behind an ISP pipeline (Raspberry Pi, RK3588, ...) or vimc in the tests. Each request
// carries the bracket sequencer's ExposureTime and AnalogueGain where the camera offers
// them, so no GPIO trigger and no latency guess are needed; each frame is stamped with the
// values its request's metadata reports as applied (else what its request asked for). A
// camera that goes away (Camera::disconnected: unplug, unbind, module removal) makes the
// state "no device"; read() then looks for it again every reopen_ms.
#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include "drivers/device_health.hpp"
#include "drivers/libcamera/libcamera_options.hpp"
#include "drivers/source.hpp"

namespace libcamera {
class CameraManager;
}

namespace probeless::libcam {

class LibcameraCamera;
struct StreamInfo;

class LibcameraFisheyeSource final : public FisheyeSource {
 public:
  // Opens the camera now if it is there; none (or no libcamera at all) is state "no
  // device" with the reason in last_error(), not an error. Throws ConfigError
  // (libcamera_camera.hpp) when the camera cannot give the configured size or format.
  explicit LibcameraFisheyeSource(LibcameraOptions options);
  ~LibcameraFisheyeSource() override;

  ReadResult read(FisheyeFrame& frame, std::chrono::milliseconds timeout) override;
  SourceState state() const override { return state_.load(); }
  std::string last_error() const override;
  std::string name() const override;
  void set_next_exposure(const ExposureStamp& exposure) override;

  // What was configured on the camera now open (nothing while there is none); for the
  // reader's thread, like read().
  const StreamInfo* stream_info() const;
  // The pipeline's sequence number of the last frame read (gaps: frames it dropped).
  std::uint32_t pipeline_sequence() const { return pipeline_sequence_; }

 private:
  bool try_open();
  bool no_device(const std::string& why);  // false, for try_open
  void lose_device(const std::string& why);

  LibcameraOptions options_;
  std::shared_ptr<libcamera::CameraManager> manager_;
  std::unique_ptr<LibcameraCamera> camera_;
  ReopenClock reopen_{options_.reopen_ms};
  TimestampNs last_frame_ns_ = 0;  // monotonic, for "stalled"
  std::uint64_t sequence_ = 0;
  std::uint32_t pipeline_sequence_ = 0;

  mutable std::mutex mutex_;  // guards requested_ (set from other threads)
  ExposureStamp requested_;
  SharedMessage error_;
  std::atomic<SourceState> state_{SourceState::NoDevice};
};

}  // namespace probeless::libcam
