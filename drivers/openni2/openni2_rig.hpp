#pragma once
// An `openni2:` spec as a rig: the OpenNI2 RGB-D source, no fisheye (pair one with
// "openni2:...+v4l2:..."), and a calibration whose colour intrinsics come from the stream's
// field of view (or the Kinect-class 525 px at 640x480 when the driver does not report one).
#include <string_view>

#include "drivers/source.hpp"

namespace probeless::openni2 {

// Throws std::invalid_argument for a bad spec, OpenniError for a missing or corrupt
// recording or a device without the configured modes.
Rig open_openni2_rig(std::string_view spec);

}  // namespace probeless::openni2
