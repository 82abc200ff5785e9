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

// fill_hole_cores_reference(), then every hole with a core in its clipped (2r+1)^2 window
// marked kNearHoleDepthMm as well: the whole near occluder (core and rim), for the stages after
// the matte that must not mistake its rim for a flicker of the sensor (the temporal
// stabiliser). CVF itself judges the rim by colour, so it takes the cores only.
DepthImage mark_near_occluders_reference(const DepthImage& depth, int radius,
                                         const ImageRGB8* colour = nullptr);

}  // namespace probeless::occlusion
