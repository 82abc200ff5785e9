#pragma once
// Rig calibration: the RGB-D colour camera, the fisheye, and the extrinsics between them,
// stored as TOML (schema in docs/camera-models.md). Parsing takes text; reading files is the
// caller's, including an OCamCalib file the TOML names (see fisheye_file).
#include <memory>
#include <string>
#include <string_view>

#include "core/camera/camera_model.hpp"
#include "core/camera/pinhole.hpp"
#include "core/pose.hpp"

namespace probeless {

struct RigCalibration {
  PinholeCamera rgb;  // colour camera; depth is registered to it
  // Null when the TOML names an OCamCalib file instead of giving the parameters inline: the
  // caller reads fisheye_file (relative to the TOML's directory) with OCamCamera::parse.
  std::shared_ptr<const CameraModel> fisheye;
  std::string fisheye_file;         // [fisheye] file = "..." as written; empty if inline
  Pose T_rig_rgb;                   // colour camera in the rig frame
  Pose T_rig_fisheye;               // fisheye camera in the rig frame
  double depth_baseline_m = 0.075;  // IR projector-camera baseline (noise model)
};

// Throws ParseError (source name and line) on malformed or incomplete TOML.
RigCalibration parse_rig_calibration(std::string_view toml_text,
                                     std::string_view source_name = "calibration.toml");
std::string to_toml(const RigCalibration& calibration);

}  // namespace probeless
