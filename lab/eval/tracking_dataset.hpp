#pragma once
// RGB-D sequences with the colour camera's true pose, as `probeless eval|bench tracking` read
// them (docs/tracking.md "Evaluation"): a TUM RGB-D folder or the sim's moving rig. Frames
// arrive one at a time (a long TUM sequence does not fit in memory), undistorted when the
// camera has distortion, so every method sees the same ideal pinhole images.
#include <memory>
#include <optional>
#include <string>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"
#include "core/time.hpp"

namespace probeless::eval {

struct TrackingFrame {
  TimestampNs timestamp_ns = 0;
  ImageRGB8 colour;
  DepthImage depth_mm;                 // registered to colour, 0 = unknown
  std::optional<Pose> T_world_camera;  // ground truth of the colour camera, when known
};

class TrackingSequence {
 public:
  virtual ~TrackingSequence() = default;
  // "tum_fr1_rpy", "sim:orbit": the report's "sequence".
  virtual const std::string& name() const = 0;
  // The ideal pinhole the frames are in (after undistortion).
  virtual const PinholeIntrinsics& camera() const = 0;
  // Where the intrinsics came from and whether the images were undistorted.
  virtual const std::string& camera_description() const = 0;
  // The colour camera's rolling-shutter readout (s), 0 for a global shutter: a property of the
  // sensor, given to the trackers that model it (the dense tracker).
  virtual double rolling_shutter_readout_s() const { return 0.0; }
  // The next frame, or nullopt at the end (or after `max_frames`). Throws on a read error.
  virtual std::optional<TrackingFrame> next() = 0;
};

// "tum:DIR[?calibration=FILE]" or "sim[:OPTIONS]" (drivers/sim/sim_rig.hpp's options; the
// trajectory defaults to orbit, realtime to 0). `max_frames` <= 0: all (the sim: 150). Throws
// std::invalid_argument (bad spec or options, sequence without ground truth) or the reader's
// error (missing folder or lists, bad calibration file), each naming what is wrong.
std::unique_ptr<TrackingSequence> open_tracking_sequence(const std::string& spec, int max_frames);

// TUM's published colour intrinsics for the sensor a folder name says (fr1/freiburg1, fr2,
// fr3), with distortion (k1 k2 p1 p2 k3) for fr1 and fr2; nullopt for another name
// (https://cvg.cit.tum.de/data/datasets/rgbd-dataset/file_formats#intrinsic_camera_calibration_of_the_kinect).
struct TumPublishedCamera {
  int sensor = 0;  // 1, 2, 3
  PinholeIntrinsics intrinsics;
  BrownDistortion distortion;
};
std::optional<TumPublishedCamera> tum_camera_for_folder(const std::string& folder_name);

}  // namespace probeless::eval
