#pragma once
// What every evaluation protocol produces: scenes ("cases") of frames with the inputs of the
// occlusion stage and the true matte. The runner (occlusion_eval.hpp) knows nothing else.
#include <optional>
#include <string>
#include <vector>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"

namespace probeless::eval {

struct EvalFrame {
  ImageRGB8 colour;
  DepthImage real_depth_mm;  // as the sensor gives it (noisy, 0 = unknown)
  ImageF virtual_depth_mm;   // 0 = no virtual object
  ImageF truth;              // visibility of the virtual object, [0, 1]
  ImageGray8 mask;           // != 0: evaluated

  // The sim protocol's extras (lab/eval/sim_dataset.hpp); empty or absent elsewhere, and the
  // metrics that need them are then not reported.
  std::optional<Pose> T_world_camera{};  // the colour camera (temporal stabilisation)
  ImageGray8 contact_band{};             // != 0: near a virtual object's contact line
  ImageGray8 near_band{};                // != 0: near an occluder the depth sensor cannot see
  ImageRGBA8 virtual_colour{};           // the virtual layer as displayed (composite metric)
  // The real scene's colour without the background mixed in at partly covered pixels; empty:
  // the observed colour is it (a renderer without mixed pixels).
  ImageRGB8 true_foreground{};
};

struct EvalCase {
  std::string name;
  std::vector<EvalFrame> frames;
  bool report_sad = false;                      // matting scenes
  std::optional<PinholeIntrinsics> intrinsics;  // with poses: the colour camera
  // Frames per window of the temporal noise: 0 = all frames (a static scene); a moving
  // camera's scene is scored over short windows (docs/occlusion.md "Sim protocol").
  int temporal_window = 0;
};

// The centre crop_w x crop_h of every image of the frame (no-op when 0 or larger).
void crop_center(EvalFrame& frame, int crop_w, int crop_h);

}  // namespace probeless::eval
