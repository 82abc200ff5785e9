#pragma once
// Occluders nearer than the depth sensor's minimum range (issue #19 item 4, thesis 3.6): a hand
// at 0.45 m in front of a Kinect-like sensor (minimum range 0.5 m) is a hole in the depth
// image, as wide as the hand. CVF calls holes "process" and lets the colour models decide; where
// the hand shares colours with the wall behind the object, colour alone cannot, and the hand
// stays transparent (docs/occlusion.md "Occluders the sensor cannot see": 13-24x the MSE of the
// same hand with depth, with the colour cap of near_occluder_reference.hpp).
//
// What tells a near occluder from the sensor's other holes is its extent: structured light
// loses depth in thin slivers (depth-edge shadows a few px wide, speckle dropouts, edges), a
// surface nearer than the minimum range over its whole area. A hole pixel whose whole
// (2r+1)^2 window is hole (the hole's "core": the hole mask eroded by r, windows clipped at the
// frame, so an arm leaving the frame stays a core) is given a depth nearer than anything
// (kNearHoleDepthMm): the depth test then makes it "in front", CVF's colour models learn the
// occluder's colours from it, and its rim (< r from measured depth) is matted by colour and
// the local prior as any process pixel is. Measured and chosen in docs/occlusion.md.
//
// Limit: a large surface the sensor cannot measure BEHIND the object (black, specular, beyond
// range, a window in sunlight) is wider than r too and hides the object the same way. Holes of
// a sunlit window's or a black screen's colour (far_hole_colour()) are therefore no core
// candidates when the colour frame is given, and the holes of walls beyond the sensor's range
// are filled far before any matte (core/beyond_range.hpp): together they take the lifted
// objects' MSE on the sim from 92.6e-3 to 4.4e-3 (2.2e-3 without cores).
#include <cstdint>

#include "core/image.hpp"

namespace probeless::occlusion {

// The depth given to a hole core: 1 mm, nearer than any virtual surface the renderer draws.
inline constexpr std::uint16_t kNearHoleDepthMm = 1;

// The radius at a frame `width` px wide for `radius_at_640` at 640 px: hole widths scale with
// the focal length in px (a depth-edge shadow is f b (1/z1 - 1/z2) px wide), so the radius
// does too. 0 when either is <= 0, else >= 1.
int hole_core_radius(int radius_at_640, int width);

// The colours of surfaces the sensor cannot measure that are no near occluder: a sunlit
// window (every channel >= kFarHoleWhiteMin) and a black screen (every channel <=
// kFarHoleBlackMax). In the sim's room 97 % of the orbit's core pixels are one or the other
// and none of the near hand's (docs/occlusion.md "Seen in the demo room itself").
inline constexpr int kFarHoleWhiteMin = 235;
inline constexpr int kFarHoleBlackMax = 45;
inline bool far_hole_colour(int r, int g, int b) {
  return (r >= kFarHoleWhiteMin && g >= kFarHoleWhiteMin && b >= kFarHoleWhiteMin) ||
         (r <= kFarHoleBlackMax && g <= kFarHoleBlackMax && b <= kFarHoleBlackMax);
}

// `depth` with every pixel whose clipped (2r+1)^2 window holds only zeros set to
// kNearHoleDepthMm; r <= 0 returns `depth` unchanged. With `colour` (same size), a zero whose
// colour is far_hole_colour() does not count as a hole for the window.
DepthImage fill_hole_cores_reference(const DepthImage& depth, int radius,
                                     const ImageRGB8* colour = nullptr);

// The radius, at 640 px width, of the window of measured depth a rim hole's colour is compared
// with (near_rim_radius() scales it): the Kinect's 9x9 window rule drops the dots of a surface
// up to 4 px beside a depth edge, so the holes of the background beside a near occluder lie
// within 4 px of the background's measured pixels, whose colour they share (docs/occlusion.md
// "The rim that follows the occluder": 3 and 4 px measured alike, 6 and 10 slightly worse, 20
// clearly).
inline constexpr int kNearRimMeasuredPx = 4;
// Where no pixel within that window is measured (a gap between fingers, the inside of a wide
// rim), the colour must be within 25 levels (Euclidean RGB, squared here) of the core's mean:
// the stabiliser's colour range (0.1 of 255), several times the camera noise, below a hand
// against a wall. Without it the gaps between the unit scene's fingers were marked
// (HoleCore.HandWithoutDepthWithinTwiceWithDepth 2.03x / 2.11x; with it 1.64x / 1.62x).
inline constexpr long long kNearRimCoreColourSq = 25 * 25;
// m at a frame `width` px wide: 4 px at 640 scaled, but never below 4 (the sim's noise model
// runs its 9x9 window in the frame's own pixels at any size).
int near_rim_radius(int width);

// fill_hole_cores_reference(), then the near occluder's rim marked kNearHoleDepthMm as well: a
// hole with a core in its clipped (2r+1)^2 window, and, with `colour`, only where its colour is
// the core's rather than the measured surface's beside it: the squared RGB distance to the mean
// colour of the core pixels in that window is below the one to the mean colour of the measured
// pixels (depth != 0) in its clipped (2m+1)^2 window, m = near_rim_radius(width) (no measured
// pixel there: within kNearRimCoreColourSq of the core's mean). Compared exactly: with n_c, S_c and
// n_m, S_m the pixels and colour sums of the two windows and c the pixel's colour, |n_c c - S_c|^2
// n_m^2 < |n_m c - S_m|^2 n_c^2, each side an exact 64-bit integer square sum times a count
// squared, both in float. Without `colour`, every hole with a core in the window (the rule before
// 2026-12-08, kept for depth without colour). The whole near occluder (core and rim) is then what
// CVF takes as "in front" and what the stages after the matte (the temporal stabiliser) are handed
// as near (docs/occlusion.md "The rim that follows the occluder").
DepthImage mark_near_occluders_reference(const DepthImage& depth, int radius,
                                         const ImageRGB8* colour = nullptr);

// The rule above for one hole with a core in its window (the device's too): the pixel's colour
// c, and the core's and the measured pixels' counts and colour sums.
inline bool rim_takes_core_colour(const int c[3], int n_core, const int core_sum[3], int n_meas,
                                  const int meas_sum[3]) {
  long long dc = 0, dm = 0;
  for (int k = 0; k < 3; ++k) {
    const long long a = static_cast<long long>(n_core) * c[k] - core_sum[k];
    const long long b = static_cast<long long>(n_meas) * c[k] - meas_sum[k];
    dc += a * a;
    dm += b * b;
  }
  if (n_meas == 0) return dc < kNearRimCoreColourSq * static_cast<long long>(n_core) * n_core;
  const float lhs = static_cast<float>(dc) * static_cast<float>(n_meas * n_meas);
  const float rhs = static_cast<float>(dm) * static_cast<float>(n_core * n_core);
  return lhs < rhs;
}

}  // namespace probeless::occlusion
