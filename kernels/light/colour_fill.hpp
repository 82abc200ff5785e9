#pragma once
// What the upward fisheye cannot see, from the forward colour camera (docs/light-capture.md
// "Below the horizon"). An environment seen from a point just above a table is half table,
// and the fisheye's 190 degrees barely reach below its own horizon: the keyframe's lower
// hemisphere is push-pull filled from the walls, so a mirror's lower half reflects wall
// colour where it should show the table. The RGB-D camera sees that table. Each colour pixel
// with depth is a world point; its direction from the environment's position picks a texel, and
// its linear colour times the colour camera's exposure e (kernels/hdr/colour_exposure.hpp) is
// radiance in the fisheye's units. Texels the fisheye observed above the horizon keep their
// value. Beyond the thesis, which lit from the fisheye alone (thesis ch. 5). Measured with
// `eval render` (2026-11-23): the chrome sphere's lower half 0.53 -> 0.25 relative RMSE, the
// whole sphere 0.256 -> 0.249 (docs/light-capture.md "Below the horizon").
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <vector>

#include "core/camera/pinhole.hpp"
#include "core/frame.hpp"
#include "core/pose.hpp"
#include "kernels/envmap/envmap_types.hpp"

namespace probeless::light {

struct ColourFillParams {
  int stride = 2;  // one colour sample every stride pixels in x and y
  // A texel without samples takes those of the smallest enclosing block of 2^k x 2^k texels
  // that has some, k <= max_level: from just above a table the texels straight down are ~2 mm
  // of table each, the colour camera's samples there ~7 x 28 mm apart (stride 2 at 1.7 m,
  // seen at a grazing 13 degrees), so whole blocks of texels see no sample.
  int max_level = 6;
  // Above the horizon a texel the fisheye did not observe takes only samples of its own block
  // at levels < this: measured with `eval render` (2026-11-23), the coarse blocks filled the
  // band of bright window just above the object's horizon (radiance ~10^4) with the wall
  // around it (~10^2): chrome sphere 0.25 -> 0.48. With 1, 2 or 3: 0.249; 0: 0.249.
  int levels_above_horizon = 1;
  // Samples farther than this times the nearest one of their block are occluded there.
  float surface_ratio = 1.15f;
  double gamma = 2.2;  // the colour camera's encoding, as ColourExposureParams
  // 8-bit: any channel >= this: clipped, a lower bound only; a block holding such a sample
  // keeps the fisheye's (bracketed) value rather than the mean of the darker samples beside it.
  int colour_saturated = 250;
  float filled_alpha = 0.5f;  // alpha of a texel filled here (observed 1, push-pull 0)
  // Below the horizon of `where` the colour camera's value replaces the fisheye's too: the
  // fisheye sees there only at the edge of its circle, and its reprojection through a room box
  // puts those samples on the floor, where from just above a table the table is (measured
  // with `eval render`: chrome-sphere error 0.25 with fill only where unobserved).
  bool replace_below_horizon = true;
};

struct ColourFillStats {
  int samples = 0;        // colour pixels with depth that were splatted
  int clipped = 0;        // of those with depth, clipped ones: they only keep the fisheye's value
  int filled_texels = 0;  // texels given colour-camera radiance
};

// texels: n x 6n (envmap layout) as seen from `where` (world), alpha 1 observed / 0 not;
// T_world_camera: the colour camera (OpenCV frame) when `frame` was taken; distortion is
// ignored (as the renderer does). Throws std::invalid_argument when the frame's colour and
// depth sizes differ from the intrinsics', or on bad params.
ColourFillStats fill_from_colour(envmap::ImageRGBAF& texels, const Eigen::Vector3d& where,
                                 const RgbdFrame& frame, const PinholeIntrinsics& k,
                                 const Pose& T_world_camera, const Eigen::Vector3d& e,
                                 const ColourFillParams& params = {});

// The same, keeping its sample list and per-level block sums between calls: the service fills
// every snapshot (4 Hz), and allocating the sums each time (7 MB at 192 px faces) faulted
// their pages in on every publish. Mean per fill inside `bench pipeline --prerender` at 192 px
// faces: 24 ms -> 12 ms (2026-11-26).
class ColourFill {
 public:
  explicit ColourFill(ColourFillParams params = {});  // std::invalid_argument on bad params
  ~ColourFill();
  ColourFill(const ColourFill&) = delete;
  ColourFill& operator=(const ColourFill&) = delete;
  ColourFillStats fill(envmap::ImageRGBAF& texels, const Eigen::Vector3d& where,
                       const RgbdFrame& frame, const PinholeIntrinsics& k,
                       const Pose& T_world_camera, const Eigen::Vector3d& e);

 private:
  struct Sample;
  struct Level;
  void collect_samples(const RgbdFrame& frame, const PinholeIntrinsics& k,
                       const Eigen::Vector3d& where, const Pose& T_world_camera,
                       const Eigen::Vector3d& e, int n);
  std::size_t sum_levels(int n);  // returns the levels filled
  ColourFillParams params_;
  std::array<float, 256> linear_{};  // 8-bit code -> linear, the camera's gamma undone
  std::vector<Sample> samples_;
  std::vector<Level> levels_;
};

}  // namespace probeless::light
