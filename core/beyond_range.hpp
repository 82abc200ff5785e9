#pragma once
// Holes in a depth image that are surfaces beyond the sensor's range (issue #19 item 4,
// docs/occlusion.md "Occluders the sensor cannot see").
//
// A structured-light sensor returns 0 both for a hand nearer than its minimum range and for a
// wall farther than its maximum (Kinect v1: 0.5-4 m in the sim's model, core/depth_noise.hpp).
// The hole cores (kernels/occlusion/cvf/hole_core_reference.hpp) take every wide hole for a
// near occluder, so a virtual object in front of the far end of a room vanished there: on the
// sim's orbit with the objects lifted 0.25 m, 93 % of the pixels the cores got wrong were the
// back wall beyond 4 m (grey-green, which no colour gate can tell from skin).
//
// What tells the two apart is the hole's rim. A wall leaving the range fades out: the measured
// pixels around its hole are themselves near the maximum range. A near hand's rim is whatever
// stands behind it. So every hole pixel whose nearest measured pixel (4-connected steps
// through the hole) is at or beyond `far_mm` is given that pixel's depth: every stage after
// sees a far surface, behind any virtual object, which is what it is. Per pixel, not per hole:
// on the sim the far wall's hole runs into the window's, whose rim is the nearer wall (a
// whole-hole vote by rim share changed the lifted-object MSE by 5 %). The limit: the part of a
// near hand whose nearest background is a far wall is taken for the wall.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/image.hpp"

namespace probeless {

struct BeyondRangeRule {
  // Rim depth that counts as far: 0.5 m inside the sim's 4 m maximum range (the axial noise
  // there is ~2 cm, core/depth_noise.hpp, so a wall fading out measures well above this).
  // 0 turns the rule off.
  std::uint16_t far_mm = 3500;
  // Hole pixels this close to the rim (4-connected steps, at 640 px width; scaled with the
  // width as hole widths are) stay holes for the matte to judge by colour: the thin holes along
  // depth edges, and the rim of an arm in front of the far wall. Measured on the lifted orbit
  // (docs/occlusion.md "Beyond the sensor's range"): boundary MSE x1e3 39.2 at 0 px, 9.5 at
  // 6, and the whole MSE 4.4 at 6 against 10.7 at 12.
  int rim_px_at_640 = 6;
};

// Reused between frames so the per-frame pass neither allocates nor clears a whole frame
// (fill_beyond_range_holes leaves `reached` all zeros).
struct BeyondRangeScratch {
  std::vector<std::uint32_t> reached;
  std::vector<std::uint32_t> queue;
};

// The rim margin at a frame `width` px wide: 0 when either is <= 0, else >= 1.
int beyond_range_rim_px(const BeyondRangeRule& rule, int width);

// Whether `depth` measures anything at or beyond rule.far_mm (false when the rule is off):
// without such a pixel no hole can be filled, and most indoor frames have none.
bool measures_beyond_range(const DepthImage& depth, const BeyondRangeRule& rule);

// Fills every beyond-range hole pixel of `depth` in place (see above) and returns how many.
// A hole with no measured rim (an all-zero frame) is left alone.
std::size_t fill_beyond_range_holes(DepthImage& depth, const BeyondRangeRule& rule,
                                    BeyondRangeScratch& scratch);

}  // namespace probeless
