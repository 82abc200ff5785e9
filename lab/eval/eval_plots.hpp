#pragma once
// The evaluator's pictures (--plots DIR): per-scene bars of MSE and of temporal noise per
// method (like the thesis's Fig. 3.5 and 3.7) as SVG (lab/eval/bar_chart.hpp), and example
// mattes of every method as PNG.
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

// <dir>/mse.svg, boundary_mse.svg, temporal_noise.svg, sad.svg: each written when some method
// has that score (temporal noise needs two frames, SAD a matting case). Throws
// std::runtime_error when a file cannot be written.
void write_bar_plots(const std::filesystem::path& dir, const EvalReport& report);

}  // namespace probeless::eval
