#pragma once
// One acquired, configured and running libcamera camera (docs/drivers.md "libcamera
// fisheye"): RAII over Camera::acquire, the FrameBufferAllocator, the mmap'd buffers and the
// requests, torn down in the reverse order. Completed requests come from libcamera's thread
// through a queue; next_frame() hands one to the caller and queues it again with the controls
// of the exposure it is given (per-request controls, no "latency" guess as for V4L2).
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/exposure.hpp"
#include "core/time.hpp"
#include "drivers/libcamera/libcamera_options.hpp"
#include "drivers/v4l2/pixel_convert.hpp"

namespace libcamera {
class Camera;
class CameraManager;
class FrameBufferAllocator;
class Request;
class Stream;
}  // namespace libcamera

namespace probeless::libcam {

// The camera is not there, went away or refused (busy, start failed): waiting may fix it.
class DeviceError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};
// The camera cannot give the configured size or format: waiting will not fix it.
class ConfigError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct StreamInfo {
  std::string camera_id;
  std::string format;  // libcamera's name, "BGR888"
  int width = 0, height = 0;
  v4l2::PixelFormat pixel;
  bool exposure_time = false;  // controls::ExposureTime offered, set per request
  bool analogue_gain = false;  // controls::AnalogueGain offered, set per request
  bool ae_enable = false;      // controls::AeEnable offered (turned off)
};

// What one completed request delivered.
struct CompletedFrame {
  std::span<const std::uint8_t> bytes;
  TimestampNs timestamp_ns = 0;  // controls::SensorTimestamp, else the buffer's timestamp
  std::uint32_t sequence = 0;    // the pipeline's frame sequence (gaps: frames it dropped)
  // What the request was queued with: the exposure its controls asked for, clamped to the
  // camera's ranges (what it applied when its metadata does not say), and the bracket place.
  ExposureStamp queued;
  // The applied values the request's metadata reports, where it does.
  std::optional<std::int32_t> exposure_us;
  std::optional<float> analogue_gain;
};

class LibcameraCamera {
 public:
  // Finds the camera (options.camera_id, or the first), acquires, configures and starts it
  // with every request queued with `initial`'s controls. DeviceError when it is absent, busy or
  // fails to start; ConfigError when it cannot give the size or format.
  LibcameraCamera(std::shared_ptr<libcamera::CameraManager> manager,
                  const LibcameraOptions& options, const ExposureStamp& initial);
  ~LibcameraCamera();
  LibcameraCamera(const LibcameraCamera&) = delete;
  LibcameraCamera& operator=(const LibcameraCamera&) = delete;

  const StreamInfo& info() const { return info_; }
  // Camera::disconnected was emitted (a hotplug pipeline's unplug: UVC in libcamera 0.0.3).
  bool disconnected() const { return disconnected_.load(); }

  // Waits up to `timeout` for a completed request; calls `use` with it, then queues the
  // request again with `next`'s controls, which come back in `queued` of the frame it
  // delivers. False on timeout, unless the camera's video nodes vanished meanwhile (an
  // unbind or rmmod that 0.0.3 reports no disconnect for): DeviceError, as on a disconnect;
  // DeviceError when the camera is gone or queueing fails. A request that failed (frame error) is
  // queued again and not given to `use`.
  bool next_frame(std::chrono::milliseconds timeout, const ExposureStamp& next,
                  const std::function<void(const CompletedFrame&)>& use);

 private:
  struct Mapping;
  void queue(std::size_t index, const ExposureStamp& stamp);
  void teardown();
  void find_video_nodes();
  bool video_nodes_gone() const;
  void abandon();  // stop, free and release in reverse order; safe on a partial start
  void on_request_completed(libcamera::Request* request);
  void on_disconnected();

  std::shared_ptr<libcamera::CameraManager> manager_;  // outlives the camera
  std::shared_ptr<libcamera::Camera> camera_;
  bool acquired_ = false, started_ = false;
  std::unique_ptr<libcamera::FrameBufferAllocator> allocator_;
  libcamera::Stream* stream_ = nullptr;
  std::vector<Mapping> mappings_;  // one per buffer, index = request cookie
  std::vector<std::unique_ptr<libcamera::Request>> requests_;
  std::vector<ExposureStamp> queued_;  // per request, as queued
  StreamInfo info_;

  std::mutex mutex_;  // guards completed_ (filled on libcamera's thread)
  std::condition_variable wake_;
  std::deque<libcamera::Request*> completed_;
  std::atomic<bool> disconnected_{false};
  struct VideoNode {
    std::string sysfs_dev;  // /sys/class/video4linux/videoN/dev
    std::string dev;        // "MAJOR:MINOR" it held at open
  };
  std::vector<VideoNode> video_nodes_;
  bool nodes_vanished_ = false;  // gone without a disconnect: abandon(), not stop()
};

// Every camera id the manager knows, comma separated, for error messages ("none" if none).
std::string camera_ids(libcamera::CameraManager& manager);

}  // namespace probeless::libcam
