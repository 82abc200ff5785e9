#pragma once
// A joint Levenberg-Marquardt refinement of a Kannala-Brandt calibration: the intrinsics (fx,
// fy, cx, cy, k1..k4) and every view's board pose together, minimising the corners'
// reprojection error through core's model (issue #18 item 1).
//
// Why, after cv::fisheye::calibrate: with CALIB_RECOMPUTE_EXTRINSIC it alternates between the
// views' poses and the intrinsics rather than solving them jointly, and stopped on the sim's
// calibration views with the radius of every ray 30-80 deg off the axis 0.3 px short (fx
// -0.29 %) while the corners themselves are unbiased to 0.04 px (docs/calibration.md "Checked
// on the sim"). The views it failed to start (calibrate_intrinsics) join the refinement once
// they are posed through its result.
#include <vector>

#include "lab/calib/board_detector.hpp"
#include "lab/calib/intrinsics.hpp"

namespace probeless::calib {

// `fisheye` is a Kannala-Brandt result for `views` (same order). Views whose reprojection RMS is
// below kFailedStartMinPx take part and are marked in_fit; the others keep their fit. Returns
// the refined calibration (RMS, poses, reprojections updated); the input unchanged when the
// refinement does not lower the cost.
Intrinsics refine_kannala_brandt(const std::vector<BoardView>& views, const Intrinsics& fisheye);

}  // namespace probeless::calib
