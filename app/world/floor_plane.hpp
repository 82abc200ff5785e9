#pragma once
// `[world] anchor = "floor"` (issue #17, docs/tracking.md "World anchoring"): with no marker,
// the dominant horizontal plane of one depth image gives the world: z up along its normal,
// the origin where the colour camera's optical axis meets it. RANSAC (Fischler & Bolles 1981)
// over the back-projected depth, hypotheses restricted to planes horizontal enough and below
// the camera, the one with the most support kept and refined by least squares on its inliers.
#include <cstdint>
#include <optional>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"

namespace probeless::world {

struct FloorParams {
  // How far the plane's normal may be from the camera's up (-y, OpenCV camera frame).
  double max_tilt_deg = 45.0;
  // Inliers within this distance of the plane. Kinect-class depth errs along the ray (sigma
  // ~1.4 mm z^2, Khoshelham & Elberink 2012; disparity steps ~3 mm z^2), so across a plane
  // seen obliquely the spread is a few mm at table range. Measured on the sim's tabletop view
  // (the table top at 0.7-1.5 m): 0.5 cm 0.02-0.15 degrees, 1 cm 0.14-0.20, 2 cm 0.04-0.06;
  // a band that grows as z^2 (0.5 cm z^2 added) took in clutter: 0.35-1.1 degrees.
  double inlier_m = 0.01;
  double min_depth_m = 0.3, max_depth_m = 4.0;
  double min_camera_height_m = 0.1;  // the camera is at least this far above the plane
  int min_inliers = 500;             // of the subsampled points (~19k at 640x480, step 4)
  int step = 4;                      // every step-th pixel in x and y is a candidate point
  int iterations = 300;
  std::uint64_t seed = 1;  // RANSAC's samples: deterministic for a given image
};

struct FloorPlane {
  Eigen::Vector3d normal;  // unit, camera frame, pointing to the camera's side (up)
  double offset = 0;       // normal . p + offset = 0 on the plane; the camera's height above it
  int inliers = 0;
  // The world the plane defines, seen from this camera: z = normal, y = the optical axis
  // projected on the plane, origin where the axis meets the plane (or, when it meets it
  // beyond max_depth_m or not at all, under the axis at the inliers' median depth).
  Pose T_camera_floor;
};

// Throws std::invalid_argument when the depth image is not the camera's size.
std::optional<FloorPlane> find_floor(const DepthImage& depth_mm, const PinholeIntrinsics& camera,
                                     const FloorParams& params = {});

}  // namespace probeless::world
