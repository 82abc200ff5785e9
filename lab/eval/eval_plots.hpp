#pragma once
// The evaluator's pictures (--plots DIR): per-scene bars of MSE and of temporal noise per
// method (like the thesis's Fig. 3.5 and 3.7) and example mattes of every method.
#include <filesystem>
#include <string>
#include <vector>

#include "lab/eval/eval_case.hpp"

namespace probeless::eval {

struct EvalReport;

// <dir>/<case>_color.png, _truth.png and _<method>.png (frame 0's matte, 255 = visible).
void write_example_mattes(const std::filesystem::path& dir, const EvalCase& c,
                          const std::vector<std::string>& methods,
                          const std::vector<std::vector<ImageF>>& alphas);

// <dir>/mse.png, boundary_mse.png, temporal_noise.png (when measured), sad.png (matting).
void write_bar_plots(const std::filesystem::path& dir, const EvalReport& report);

}  // namespace probeless::eval
