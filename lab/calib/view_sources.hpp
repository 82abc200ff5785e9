#pragma once
// Where calibration views come from (docs/calibration.md "Input"): a folder of one camera's
// images, two folders of the rig's cameras matched by file name, or a recording made with
// `probeless record` (docs/formats.md "Recording format"), its fisheye frames paired with the
// colour frame nearest in time.
#include <filesystem>
#include <string>
#include <vector>

#include "core/frame.hpp"
#include "core/image.hpp"

namespace probeless::calib {

// The images in `dir` (by extension: jpg, jpeg, png, bmp, tif, tiff, pgm, ppm), sorted by
// name. Throws std::runtime_error for a missing directory or one without images.
std::vector<std::filesystem::path> list_images(const std::filesystem::path& dir);

// One moment seen by both cameras.
struct StereoImages {
  std::string name;  // file stem or "frame SEQUENCE"
  ImageGray8 rgb, fisheye;
};

struct ImagePair {
  std::string name;  // the common stem
  std::filesystem::path rgb, fisheye;
};
// Images whose stems match in both folders (rgb/0001.png with fisheye/0001.jpg). Throws
// std::runtime_error when no name matches; `unmatched` counts the images left alone.
std::vector<ImagePair> matching_images(const std::filesystem::path& rgb_dir,
                                       const std::filesystem::path& fisheye_dir, int* unmatched);

// Fisheye frames of the recording paired with the colour frame nearest in time (within
// kMaxPairGapMs), at most `max_pairs` of them spread evenly over the recording. Throws
// ParseError for a broken recording, std::runtime_error when it has no pairs. The recorded
// calibration's depth baseline (a property of the depth sensor, not calibrated here) is
// returned in `depth_baseline_m`.
std::vector<StereoImages> recording_pairs(const std::filesystem::path& dir, int max_pairs,
                                          double* depth_baseline_m);
inline constexpr double kMaxPairGapMs = 20.0;  // under one frame period at 30 fps

// A raw fisheye frame as 8-bit gray for the board detector: black level removed, scaled so
// that the 99th percentile is white, gamma 1/2.2 to lift the dark board.
ImageGray8 fisheye_gray(const FisheyeFrame& frame);

}  // namespace probeless::calib
