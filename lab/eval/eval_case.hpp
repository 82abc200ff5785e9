#pragma once
// What every evaluation protocol produces: scenes ("cases") of frames with the inputs of the
// occlusion stage and the true matte. The runner (occlusion_eval.hpp) knows nothing else.
#include <string>
#include <vector>

#include "core/image.hpp"

namespace probeless::eval {

struct EvalFrame {
  ImageRGB8 colour;
  DepthImage real_depth_mm;  // as the sensor gives it (noisy, 0 = unknown)
  ImageF virtual_depth_mm;   // 0 = no virtual object
  ImageF truth;              // visibility of the virtual object, [0, 1]
  ImageGray8 mask;           // != 0: evaluated
};

struct EvalCase {
  std::string name;
  std::vector<EvalFrame> frames;
  bool report_sad = false;  // matting scenes
};

// The centre crop_w x crop_h of every image of the frame (no-op when 0 or larger).
void crop_center(EvalFrame& frame, int crop_w, int crop_h);

}  // namespace probeless::eval
