#pragma once
// A Kinect-like structured-light depth sensor as a pure function of a clean depth map
// (docs/sim.md "Depth noise"). After Handa et al. 2014 (ICL-NUIM, the simkinect code):
// a random 2-D shift of the pixel grid with bilinear resampling, disparity d = f b / z
// quantised to 1/8 px, and the simkinect 9x9 window rule on a projected dot pattern that
// leaves holes on depth edges; the axial noise of Nguyen, Izadi & Lovell 2012,
// sigma_z(z) = 0.0012 + 0.0019 (z - 0.4)^2 m, is what the output's error has in total.
// No I/O and no threads: the synthetic rig and the occlusion evaluator (Middlebury) share it.
#include <cstdint>

#include "core/image.hpp"

namespace probeless {

struct KinectNoiseParams {
  double baseline_m = 0.075;                    // IR projector-camera baseline
  double shift_sigma_px = 0.5;                  // per-pixel random 2-D shift of the grid (ICL-NUIM)
  double disparity_quantum_px = 1.0 / 8;        // sub-pixel disparity resolution
  double min_depth_m = 0.5, max_depth_m = 4.0;  // outside this range: no depth
  // Axial noise sigma_z(z) = a + b (z - z0)^2 (Nguyen et al. 2012, fitted on a Kinect v1).
  double axial_a_m = 0.0012, axial_b_per_m = 0.0019, axial_z0_m = 0.4;
  // Window rule (simkinect filterDisp): a dot survives when more than 1/window_valid_ratio of
  // the dots in its window have a disparity within window_inlier_px * 1.44 r^2 of the window
  // mean (r: distance to the centre in px, 1 at the centre); survivors fill the pixels within
  // fill_radius_px that no nearer survivor claims.
  int window_size_px = 9;
  double window_inlier_px = 0.1;
  double window_valid_ratio = 1.2;
  int fill_radius_px = 3;
  int dot_spacing_px = 3;  // one projected dot per dot_spacing^2 cell, at a fixed jitter
};

// Standard deviation of the depth error at depth z (metres), the model's target.
double kinect_axial_sigma_m(double z_m, const KinectNoiseParams& params = {});

// clean_depth_mm: 0 = no surface. focal_px: the camera's fx. Deterministic in seed (the
// same inputs give bit-identical output on every machine and thread count).
DepthImage apply_kinect_noise(const DepthImage& clean_depth_mm, double focal_px, std::uint64_t seed,
                              const KinectNoiseParams& params = {});

}  // namespace probeless
