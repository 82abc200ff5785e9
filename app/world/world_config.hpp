#pragma once
// What [tracking] and [world] of the service's config say (app/pipeline/service_config.cpp
// parses them; docs/configuration.md lists the keys, docs/tracking.md explains them).
#include <string>

namespace probeless {

// [tracking]: where the rig is (docs/tracking.md "Poses in the service").
struct TrackingConfig {
  // "dense": the RGB-D tracker (kernels/tracking/dense_tracker.hpp); "truth": the source's
  // rig pose (the sim, a recording with a trajectory), for evaluation; "off": a static rig.
  std::string method = "dense";
  double min_depth_m = 0.3;  // depth the tracker uses (DenseTrackerParams)
  double max_depth_m = 4.0;
  // Where the dense tracker runs: "cpu" (its plain C++ path, on the processing thread) or
  // "opencl" (its kernels, on the frame path's queue). Both give the same poses
  // (tests/kernels/tracking); which is faster depends on the device: see docs/tracking.md
  // "Device and CPU" and the measurement behind the default in docs/performance.md.
  std::string device = "cpu";
  // The colour sensor's rolling-shutter readout, top row to bottom row (DenseTrackerParams::
  // rolling_shutter_readout_s; Kerl et al., ICCV 2015). 0: a global shutter (the sim). A Kinect
  // v1 or a TUM RGB-D recording: 0.028, the readout Kerl et al. simulate for RGB-D sensors
  // (docs/tracking.md: ATE on fr1/rpy 0.0178 -> 0.0130 m with it).
  double rolling_shutter_readout_s = 0.0;
};

// [world]: where the world is (docs/tracking.md "World anchoring").
struct WorldConfig {
  // "rig": the rig's world as the source gives it (today's fixed rig); "floor": the dominant
  // horizontal plane at start-up, z up, origin under the optical axis; "marker": the board or
  // ArUco marker named by `marker`, z up along its normal, origin at its centre.
  std::string anchor = "rig";
  // core/board_spec.hpp: charuco:COLSxROWS:SQ_MM:MK_MM:DICT or aruco:ID:SIZE_MM:DICT. The
  // default is the board on the sim's table (drivers/sim, docs/sim.md).
  std::string marker = "charuco:5x4:80:60:4x4_50";
  // Re-anchoring on a new marker sighting moves the world by at most this much per frame (at
  // the world origin, rotation included), so a re-anchored object glides instead of jumping.
  double max_step_mm = 2.0;
  // `floor`: how far from the camera's down direction the plane's normal may be.
  // 45: a hand-held rig looking at a table is pitched down 30-40 degrees (the sim's
  // `trajectory=tabletop` view is 38), so 30 would refuse the table it looks at.
  double floor_max_tilt_deg = 45.0;
};

}  // namespace probeless
