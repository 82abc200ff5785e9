#pragma once
// The sim protocol of `eval occlusion` (docs/occlusion.md "Sim protocol"): the synthetic rig
// (drivers/sim, docs/sim.md) with a moving camera and moving occluders, the service's virtual
// objects rendered by the service's renderer at the colour camera's true pose, and the truth
// from the sim's clean depth: the virtual object is visible where the real surface is not in
// front of it. Besides the matte's truth each frame carries the camera pose (for temporal
// stabilisation), the contact band, the near-occluder band and the virtual colour.
#include <string_view>
#include <vector>

#include "core/frame.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "lab/eval/eval_case.hpp"

namespace probeless::eval {

struct SimProtocolOptions {
  sim::SimOptions sim;
  int frames = 90;  // 3 s at 30 fps
  // Contact line: on-object pixels where the real surface is within this of the virtual one
  // (clean depth); the band is every evaluated pixel within band_px of one.
  double contact_mm = 10.0;
  int band_px = 10;
  // Metres the virtual objects are raised above where the service puts them (`lift=`, 0..2):
  // on the orbit, 0.25 m brings them in front of the room's window and TV screen, far surfaces
  // without depth, which is where the hole cores can wrongly hide an object (docs/occlusion.md
  // "Occluders the sensor cannot see").
  double lift_m = 0.0;
};

// `options`: the part after "sim:" (may be empty): sim options (parse_sim_options) laid over
// the protocol's defaults trajectory=tabletop, start=1.5, near_occluder=1, realtime=0; its
// `frames` is the protocol's frame count (default 90); `lift` is the protocol's own. Throws
// std::invalid_argument naming a bad key.
SimProtocolOptions parse_sim_protocol(std::string_view options);

// One case, "sim/<trajectory>[+near]", of options.frames frames. Needs EGL (the renderer).
std::vector<EvalCase> sim_cases(const SimProtocolOptions& options);

// The sim's mixed pixels (FrameTruth::mixed_pixels) into a frame whose truth, mask, colour
// and virtual depth are set: where the virtual surface lies between a pixel's two layers its
// truth becomes the far layer's coverage and its true foreground the near layer's colour
// (f.true_foreground: the observed colour elsewhere). Nothing without mixed pixels.
void apply_mixed_pixels(const std::vector<MixedPixel>& mixed, EvalFrame& f);

// 255 on every pixel within `radius` (Chebyshev) of a non-zero pixel of `seeds`, else 0: the
// contact and near-occluder bands before they are cut to the evaluated pixels.
ImageGray8 dilate_mask(const ImageGray8& seeds, int radius);

}  // namespace probeless::eval
