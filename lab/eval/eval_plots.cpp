#include "lab/eval/eval_plots.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>

#include "drivers/io/png.hpp"
#include "lab/eval/occlusion_eval.hpp"

namespace probeless::eval {
namespace fs = std::filesystem;
namespace {

// A 5x7 bitmap font: each glyph is 7 rows of 5 bits (MSB = left column).
const std::map<char, std::array<std::uint8_t, 7>>& font() {
  static const std::map<char, std::array<std::uint8_t, 7>> f = {
      {'0', {14, 17, 19, 21, 25, 17, 14}}, {'1', {4, 12, 4, 4, 4, 4, 14}},
      {'2', {14, 17, 1, 2, 4, 8, 31}},     {'3', {31, 2, 4, 2, 1, 17, 14}},
      {'4', {2, 6, 10, 18, 31, 2, 2}},     {'5', {31, 16, 30, 1, 1, 17, 14}},
      {'6', {6, 8, 16, 30, 17, 17, 14}},   {'7', {31, 1, 2, 4, 8, 8, 8}},
      {'8', {14, 17, 17, 14, 17, 17, 14}}, {'9', {14, 17, 17, 15, 1, 2, 12}},
      {'A', {14, 17, 17, 31, 17, 17, 17}}, {'B', {30, 17, 17, 30, 17, 17, 30}},
      {'C', {14, 17, 16, 16, 16, 17, 14}}, {'D', {28, 18, 17, 17, 17, 18, 28}},
      {'E', {31, 16, 16, 30, 16, 16, 31}}, {'F', {31, 16, 16, 30, 16, 16, 16}},
      {'G', {14, 17, 16, 23, 17, 17, 15}}, {'H', {17, 17, 17, 31, 17, 17, 17}},
      {'I', {14, 4, 4, 4, 4, 4, 14}},      {'J', {7, 2, 2, 2, 2, 18, 12}},
      {'K', {17, 18, 20, 24, 20, 18, 17}}, {'L', {16, 16, 16, 16, 16, 16, 31}},
      {'M', {17, 27, 21, 21, 17, 17, 17}}, {'N', {17, 17, 25, 21, 19, 17, 17}},
      {'O', {14, 17, 17, 17, 17, 17, 14}}, {'P', {30, 17, 17, 30, 16, 16, 16}},
      {'Q', {14, 17, 17, 17, 21, 18, 13}}, {'R', {30, 17, 17, 30, 20, 18, 17}},
      {'S', {15, 16, 16, 14, 1, 1, 30}},   {'T', {31, 4, 4, 4, 4, 4, 4}},
      {'U', {17, 17, 17, 17, 17, 17, 14}}, {'V', {17, 17, 17, 17, 17, 10, 4}},
      {'W', {17, 17, 17, 21, 21, 21, 10}}, {'X', {17, 17, 10, 4, 10, 17, 17}},
      {'Y', {17, 17, 17, 10, 4, 4, 4}},    {'Z', {31, 1, 2, 4, 8, 16, 31}},
      {'.', {0, 0, 0, 0, 0, 12, 12}},      {'-', {0, 0, 0, 31, 0, 0, 0}},
      {'_', {0, 0, 0, 0, 0, 0, 31}},       {'/', {1, 1, 2, 4, 8, 16, 16}},
      {' ', {0, 0, 0, 0, 0, 0, 0}},        {'(', {2, 4, 8, 8, 8, 4, 2}},
      {')', {8, 4, 2, 2, 2, 4, 8}},        {'+', {0, 4, 4, 31, 4, 4, 0}}};
  return f;
}

using Rgb = std::array<std::uint8_t, 3>;

void fill(ImageRGB8& img, int x0, int y0, int x1, int y1, Rgb c) {
  for (int y = std::max(0, y0); y < std::min(img.height(), y1); ++y)
    for (int x = std::max(0, x0); x < std::min(img.width(), x1); ++x)
      for (int k = 0; k < 3; ++k) img.at(x, y, k) = c[k];
}

// Text in the 5x7 font (upper case only), 6 px per character.
void text(ImageRGB8& img, int x, int y, const std::string& s, Rgb c) {
  for (char ch : s) {
    const auto it = font().find(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
    if (it != font().end())
      for (int r = 0; r < 7; ++r)
        for (int b = 0; b < 5; ++b)
          if (it->second[r] & (16 >> b)) fill(img, x + b, y + r, x + b + 1, y + r + 1, c);
    x += 6;
  }
}

const Rgb kPalette[] = {{214, 39, 40},   {31, 119, 180}, {255, 127, 14},  {44, 160, 44},
                        {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {127, 127, 127}};

void bar_plot(const fs::path& path, const std::string& title, const EvalReport& r,
              std::optional<double> (*get)(const MethodScore&)) {
  const int bar = 9, gap = 18, left = 60, top = 40, plot_h = 220, bottom = 60;
  const int group = bar * static_cast<int>(r.methods.size()) + gap;
  const int groups = static_cast<int>(r.scenes.size()) + 1;  // + mean
  const int w = std::max(left + groups * group + 20, 560), h = top + plot_h + bottom;
  double vmax = 0;
  for (const auto& sc : r.scenes)
    for (const auto& [m, s] : sc.methods)
      if (auto v = get(s)) vmax = std::max(vmax, *v);
  if (vmax <= 0) return;
  // Axis top: 1, 2 or 5 times a power of ten above the largest value.
  const double p = std::pow(10.0, std::floor(std::log10(vmax)));
  const double top_v = vmax <= p ? p : vmax <= 2 * p ? 2 * p : vmax <= 5 * p ? 5 * p : 10 * p;
  ImageRGB8 img(w, h, 255);
  text(img, left, 8, title, {0, 0, 0});
  for (int t = 0; t <= 4; ++t) {
    const int y = top + plot_h - plot_h * t / 4;
    fill(img, left - 3, y, w - 10, y + 1, t ? Rgb{220, 220, 220} : Rgb{0, 0, 0});
    text(img, 2, y - 3, fmt::format("{:.2g}", top_v * t / 4), {0, 0, 0});
  }
  auto draw_group = [&](int g, const std::string& name,
                        const std::map<std::string, MethodScore>& s) {
    const int x0 = left + g * group + gap / 2;
    for (std::size_t m = 0; m < r.methods.size(); ++m)
      if (auto v = get(s.at(r.methods[m]))) {
        const int bh = static_cast<int>(std::lround(plot_h * std::min(1.0, *v / top_v)));
        fill(img, x0 + int(m) * bar, top + plot_h - bh, x0 + int(m + 1) * bar - 1, top + plot_h,
             kPalette[m % 8]);
      }
    // Names alternate between two rows so that long ones do not run into each other.
    const auto room = static_cast<std::size_t>(2 * group / 6 - 1);
    const auto label = name.size() > room ? name.substr(0, room) : name;
    text(img, x0, top + plot_h + 6 + (g % 2) * 10, label, {0, 0, 0});
  };
  for (std::size_t g = 0; g < r.scenes.size(); ++g)
    draw_group(int(g), r.scenes[g].name, r.scenes[g].methods);
  draw_group(int(r.scenes.size()), "mean", r.mean);
  int lx = left;
  for (std::size_t m = 0; m < r.methods.size(); ++m) {
    fill(img, lx, h - 22, lx + 8, h - 14, kPalette[m % 8]);
    text(img, lx + 11, h - 22, r.methods[m], {0, 0, 0});
    lx += 14 + 6 * static_cast<int>(r.methods[m].size());
  }
  write_png(path, img);
}

std::string file_stem(const std::string& case_name) {
  std::string s = case_name;
  std::replace(s.begin(), s.end(), '/', '_');
  return s;
}

ImageGray8 to_gray(const ImageF& a) {
  ImageGray8 g(a.width(), a.height());
  for (std::size_t i = 0; i < a.pixel_count(); ++i)
    g.data()[i] = static_cast<std::uint8_t>(std::lround(std::clamp(a.data()[i], 0.0F, 1.0F) * 255));
  return g;
}

}  // namespace

void write_example_mattes(const fs::path& dir, const EvalCase& c,
                          const std::vector<std::string>& methods,
                          const std::vector<std::vector<ImageF>>& alphas) {
  if (c.frames.empty()) return;
  fs::create_directories(dir);
  const auto stem = file_stem(c.name);
  write_png(dir / (stem + "_color.png"), c.frames[0].colour);
  write_png(dir / (stem + "_truth.png"), to_gray(c.frames[0].truth));
  for (std::size_t m = 0; m < methods.size(); ++m)
    if (!alphas[m].empty())
      write_png(dir / (stem + "_" + methods[m] + ".png"), to_gray(alphas[m][0]));
}

void write_bar_plots(const fs::path& dir, const EvalReport& r) {
  fs::create_directories(dir);
  bar_plot(dir / "mse.png", "MSE per scene and method", r,
           [](const MethodScore& s) { return std::optional(s.mse); });
  bar_plot(dir / "boundary_mse.png", "MSE within 10 px of true silhouettes", r,
           [](const MethodScore& s) { return s.boundary_mse; });
  bar_plot(dir / "temporal_noise.png", "temporal noise (per-pixel variance across frames)", r,
           [](const MethodScore& s) { return s.temporal_noise; });
  bar_plot(dir / "sad.png", "SAD / 1000", r, [](const MethodScore& s) { return s.sad; });
}

}  // namespace probeless::eval
