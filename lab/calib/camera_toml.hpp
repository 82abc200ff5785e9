#pragma once
// The camera files `probeless calibrate` writes (docs/calibration.md "Output"), always through
// core's to_toml so that the keys and numbers are exactly what the service reads
// (core/calibration.hpp, docs/camera-models.md "Rig calibration TOML").
#include <filesystem>
#include <string>

#include "core/calibration.hpp"
#include "core/camera/camera_model.hpp"

namespace probeless::calib {

// Writes one camera to `path`:
// - `path` exists: it must be a rig calibration; the camera replaces its colour camera (a
//   pinhole) or its fisheye (any other model) and the rest is kept, so the files of several
//   runs add up to the rig's calibration.
// - otherwise a pinhole becomes an RGB-D-only rig calibration (its [rgb], identity
//   extrinsics), which the service and `tum:DIR?calibration=` load as it is; a fisheye becomes
//   the [fisheye] table of the rig file, to be joined with the colour camera's.
// Returns what was done, for the command to print. Throws std::runtime_error naming the file.
std::string write_camera_toml(const std::filesystem::path& path,
                              std::shared_ptr<const CameraModel> camera);

// The whole rig (calibrate --recording / --rgb-images): to_toml, written whole or not at all.
void write_rig_toml(const std::filesystem::path& path, const RigCalibration& rig);

// An OCamCalib calib_results.txt as OCamCamera (core/camera/ocam.hpp) reads it. Throws
// ParseError naming the file and line, std::runtime_error for a missing or oversized file.
std::shared_ptr<const CameraModel> read_ocam_file(const std::filesystem::path& path);

}  // namespace probeless::calib
