#pragma once
// The recorded protocol (the thesis's green-screen recordings; docs/formats.md "Occlusion
// evaluation sequences"): per frame a colour PNG, a 16-bit depth PNG (mm), the virtual depth
// (PFM, mm, 0 = no object) and the true visibility matte (8-bit PNG), optionally a mask.
#include <filesystem>
#include <vector>

#include "lab/eval/eval_case.hpp"

namespace probeless::eval {

// One case per sequence: `root` itself when it holds frames, else each subdirectory that does.
std::vector<EvalCase> recorded_cases(const std::filesystem::path& root);

}  // namespace probeless::eval
