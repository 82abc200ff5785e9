#pragma once
#include <ostream>

namespace probeless::cli {

// The "libcamera cameras" section of `probeless devices`: each camera's id (the one a
// `libcamera:ID` spec names), model, whether it takes ExposureTime and AnalogueGain per
// request (the bracket cycle needs them), its other controls and its formats.
void print_libcamera_cameras(std::ostream& out);

}  // namespace probeless::cli
