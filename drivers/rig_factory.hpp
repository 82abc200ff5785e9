#pragma once
// One string names a rig, everywhere a command takes --source (docs/formats.md "Source
// specs"):
//   sim | sim:<options>            the synthetic rig (drivers/sim/sim_rig.hpp)
//   replay:DIR[?options]           a recording (drivers/replay/replay_source.hpp)
//   tum:DIR[?options]              a TUM RGB-D sequence (drivers/replay/tum_source.hpp)
// Replay and TUM options, ',' or '&' separated: realtime=0|1 (default 1), loop=0|1 (0),
// rebase=0|1 (0); TUM also calibration=FILE.
//   v4l2:DEVICE[?options]          the synthetic rig's RGB-D with a V4L2 fisheye
//   RGBD_SPEC+v4l2:DEVICE[?opts]   any of the above's RGB-D with a V4L2 fisheye
//   openni2:[URI][?options]        an OpenNI2 RGB-D sensor (the first one without a URI)
//   openni2:FILE.oni[?options]     an OpenNI2 recording (drivers/openni2/openni2_options.hpp)
// V4L2 options: drivers/v4l2/v4l2_options.hpp, plus calibration=FILE (the rig's calibration
// TOML, replacing the RGB-D rig's; docs/drivers.md).
#include <memory>
#include <string>
#include <string_view>

#include "drivers/source.hpp"

namespace probeless {

// Throws std::invalid_argument for an unknown scheme or option (the message lists the valid
// ones), ParseError / ImageFileError for a malformed recording or sequence.
Rig open_rig(std::string_view spec);

// A fisheye alone: "v4l2:DEVICE[?options]". Throws std::invalid_argument for an unknown
// scheme or option, v4l2::ConfigError when the device cannot give the configured format.
std::unique_ptr<FisheyeSource> open_fisheye_source(std::string_view spec);

// "sim, sim:<options>, replay:DIR[?options], tum:DIR[?options]" for help texts.
std::string rig_spec_help();

}  // namespace probeless
