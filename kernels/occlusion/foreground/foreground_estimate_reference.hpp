#pragma once
// Foreground colour at fractional alpha (issue #19 item 5; thesis 3.2.7 and 3.6;
// docs/compositing.md "Foreground colour at soft edges"). Where the matte is fractional the
// camera saw a mix I = a F + (1 - a) B of the real occluder F (opacity a = 1 - visibility) and
// the real background B that the virtual object replaces. Compositing the observed I carries B
// into the object; compositing F does not. Per fractional pixel:
//   F_l, B_l: the means of the confident occluder pixels (on the object, visibility <=
//     confident) and of the confident background pixels (visibility >= 1 - confident) in the
//     (2r+1)^2 window, weighted 1 / (1 + d^2) so the nearest colours count most (the thesis
//     takes the nearest confident foreground colour);
//   the smallest change (F, B) of (F_l, B_l) that explains I exactly (Levin, Lischinski & Weiss
//     2008's compositing equation as a constraint): with r = I - a F_l - (1 - a) B_l,
//     F = F_l + a r / (a^2 + (1 - a)^2), clamped to [0, 1]. The denominator is >= 1/2, so the
//     estimate stays stable at small a (where it matters least), unlike (I - (1 - a) B) / a.
// In linear light (the mix happens in the scene, not in the camera's gamma): decode with the
// camera's gamma (2.2, CameraResponse), estimate, encode. Pixels off the object, with
// visibility 0 or 1, or without confident samples of both kinds in the window keep I.
#include <array>

#include "core/image.hpp"

namespace probeless::occlusion {

struct ForegroundEstimateParams {
  // Window radius: CVF's soft edge is the wide filter's 3 px plus the feather's 1 px wide on
  // each side of the 0.5 crossing (docs/occlusion.md), so confident pixels of both sides lie
  // within 4-5 px of every fractional one; 6 reaches them from one-sided windows too.
  int radius_px = 6;
  // Visibility <= this (occluder) or >= 1 - this (background) is a confident sample.
  float confident = 0.05F;
  double gamma = 2.2;  // the colour camera's power-law gamma (CameraResponse::gamma)
};

// Throws std::invalid_argument for a radius outside [1, 16], confident outside [0, 0.5), a
// gamma not finite or outside (0, 10].
void validate(const ForegroundEstimateParams& params);

// (v / 255)^gamma for v = 0..255, rounded once to float: shared by the reference and the device.
std::array<float, 256> decode_table(double gamma);

// The colour frame with F in place of I at fractional pixels. virtual_depth_mm > 0 marks the
// object; visibility is the occlusion stage's alpha. Throws std::invalid_argument when sizes
// differ.
ImageRGB8 foreground_estimate_reference(const ImageRGB8& colour, const ImageF& virtual_depth_mm,
                                        const ImageF& visibility,
                                        const ForegroundEstimateParams& params = {});

}  // namespace probeless::occlusion
