#pragma once
// The matting protocol on alphamatting.com's training images (docs/occlusion.md): the trimap
// becomes synthetic depths so that every method runs its ordinary path. The virtual object
// covers the whole image at 1000 mm; trimap white (foreground, in front of the virtual
// object) is real depth 500 mm, black 2000 mm, grey unknown (0), so the categories are
// exactly infront / behind / process. The true visibility is 1 - ground-truth alpha,
// evaluated on the trimap's unknown region.
#include <filesystem>
#include <vector>

#include "lab/eval/eval_case.hpp"

namespace probeless::eval {

inline constexpr float kMattingVirtualMm = 1000.0F;

// One case per (image, trimap) pair: "GT01/Trimap1", ... Needs input/, gt/ and Trimap*/
// under `root`; throws ImageFileError naming what is missing.
std::vector<EvalCase> alphamatting_cases(const std::filesystem::path& root);

// The synthetic inputs of one trimap (0 / 128 / 255; < 64 black, > 192 white, else unknown).
EvalFrame matting_frame(const ImageRGB8& colour, const ImageGray8& trimap, const ImageGray8& alpha);

}  // namespace probeless::eval
