#pragma once
// One opened OpenNI2 device or recording with its colour and depth streams started
// (docs/drivers.md "OpenNI2 RGB-D"). Construction opens, configures and starts; destruction
// stops and closes. Frames come out one stream at a time; pairing them is the source's job.
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "core/image.hpp"
#include "drivers/openni2/openni2_options.hpp"
#include "drivers/openni2/openni2_runtime.hpp"

namespace probeless::openni2 {

// The device is not there (unplugged, never plugged, or held by another process): a state
// the source waits out, unlike OpenniError (a missing or corrupt recording, a mode the
// device does not offer), which waiting would not fix.
class DeviceMissing : public OpenniError {
 public:
  using OpenniError::OpenniError;
};

struct CameraInfo {
  std::string uri, vendor, name;
  std::uint16_t usb_vendor = 0, usb_product = 0;
  bool is_file = false;
  VideoModeInfo colour, depth;
  bool registered = false;                         // depth registered to colour by the device
  bool synced = false;                             // the device's depth/colour frame sync is on
  int colour_frames = 0, depth_frames = 0;         // in a recording; 0 for a device
  float colour_hfov_rad = 0, colour_vfov_rad = 0;  // 0 when the driver does not say
};

enum class StreamKind { Colour, Depth };

struct StreamFrame {
  StreamKind kind = StreamKind::Colour;
  std::uint64_t device_us = 0;  // the device's (or recording's) timestamp
  int index = 0;                // OpenNI's frame index (1-based in recordings)
};

class Openni2Camera {
 public:
  // Throws DeviceMissing or OpenniError (both name the device and say why).
  Openni2Camera(const Openni2Options& options, std::shared_ptr<OpenniRuntime> runtime);
  ~Openni2Camera();
  Openni2Camera(const Openni2Camera&) = delete;
  Openni2Camera& operator=(const Openni2Camera&) = delete;

  const CameraInfo& info() const { return info_; }

  // Waits up to `timeout` for a frame on either stream and converts it into `colour` or
  // `depth` (mm). False when none came. Throws OpenniError when a stream fails.
  bool next(std::chrono::milliseconds timeout, StreamFrame& frame, ImageRGB8& colour,
            DepthImage& depth);

  // Turns the device's depth/colour frame sync off (see Openni2RgbdSource::on_stall).
  void disable_sync();

  // A recording without repeat has delivered the last frame of both streams.
  bool finished() const;

 private:
  struct Handles;
  void configure_streams(const Openni2Options& options);
  void close();  // safe twice; a Dummy device's handles are parked (openni2_camera.cpp)
  std::shared_ptr<OpenniRuntime> runtime_;  // first member: OpenNI outlives the handles
  std::unique_ptr<Handles> handles_;
  CameraInfo info_;
  bool repeat_ = false;
  int last_colour_index_ = 0, last_depth_index_ = 0;
};

// Closed Dummy devices whose streams are kept until their never-joined driver threads have
// surely seen the stop (openni2_camera.cpp, kParkFor).
std::size_t parked_dummy_devices();

}  // namespace probeless::openni2
