#pragma once
// A rig calibration TOML file (core/calibration.hpp) read from disk, with the OCamCalib file
// it may name loaded from beside it, so that the result always has its fisheye model.
#include <filesystem>

#include "core/calibration.hpp"

namespace probeless::replay {

// Throws ParseError naming the TOML (or the OCamCalib file) and line.
RigCalibration load_rig_calibration(const std::filesystem::path& toml_path);

// The calibration as a recording stores it: a fisheye model loaded from a file is written
// inline, so that the recording is self-contained.
RigCalibration self_contained(RigCalibration calibration);

}  // namespace probeless::replay
