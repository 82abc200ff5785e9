#pragma once
// One open, streaming V4L2 capture device: QUERYCAP, format and frame-interval negotiation,
// mmap'd buffers, manual exposure/gain controls. Construction does it all or throws; the
// destructor stops streaming and releases the buffers and the descriptor. The fisheye source
// (v4l2_fisheye_source.hpp) owns one while the device is there and makes a new one after it
// returns. Internal to drivers/v4l2.
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "drivers/v4l2/pixel_convert.hpp"
#include "drivers/v4l2/v4l2_handles.hpp"
#include "drivers/v4l2/v4l2_options.hpp"

namespace probeless::v4l2 {

// The device went away or failed (errno kept): the source reports "no device" and reopens.
class DeviceError : public std::runtime_error {
 public:
  DeviceError(const std::string& what, int err) : std::runtime_error(what), err_(err) {}
  int error() const { return err_; }

 private:
  int err_;
};

// The device is there but cannot do what the options ask (size, format): a configuration
// mistake, not a fault to wait out.
class ConfigError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ControlRange {
  bool present = false;
  std::int64_t min = 0, max = 0, step = 1, def = 0;
};

struct CaptureInfo {
  std::string path, card, driver, bus_info;
  std::string fourcc;  // the negotiated pixel format
  int width = 0, height = 0;
  double fps = 0;                // the frame interval the driver accepted, as a rate
  bool fps_from_device = false;  // false: the driver has no V4L2_CAP_TIMEPERFRAME
  PixelFormat pixel;
  ControlRange exposure;  // V4L2_CID_EXPOSURE_ABSOLUTE, 100 us units
  ControlRange gain;      // V4L2_CID_GAIN, driver units
};

struct AppliedControls {
  std::optional<std::int64_t> exposure;  // read back after setting; empty: no such control
  std::optional<std::int64_t> gain;
};

class V4l2Camera {
 public:
  // Throws DeviceError when the device is missing or fails, ConfigError when it cannot give
  // the configured size or format.
  explicit V4l2Camera(const V4l2Options& options);
  ~V4l2Camera();
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  const CaptureInfo& info() const { return info_; }

  // Waits up to `timeout` for a filled buffer; hands its bytes, CLOCK_MONOTONIC timestamp
  // and the driver's frame sequence number (which counts frames it dropped) to `consume`,
  // then gives the buffer back to the driver. False when no frame came (or
  // the driver flagged it corrupt). Throws DeviceError.
  using Consumer = std::function<void(std::span<const std::uint8_t>, TimestampNs, std::uint32_t)>;
  bool next_frame(std::chrono::milliseconds timeout, const Consumer& consume);

  // Sets the controls that exist (clamped to their range and step) and reads them back.
  AppliedControls set_controls(std::optional<std::int64_t> exposure,
                               std::optional<std::int64_t> gain);

 private:
  void open_device(const V4l2Options& options);
  void negotiate_format(const V4l2Options& options);
  void set_frame_interval(double fps);
  void start_streaming(int buffers);
  void take_manual_control();
  ControlRange query_control(std::uint32_t id) const;

  UniqueFd fd_;
  std::vector<MappedBuffer> buffers_;
  bool streaming_ = false;
  CaptureInfo info_;
};

}  // namespace probeless::v4l2
