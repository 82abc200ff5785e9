#include "lab/eval/alphamatting_dataset.hpp"

#include <algorithm>

#include "drivers/io/png.hpp"

namespace probeless::eval {
namespace fs = std::filesystem;

EvalFrame matting_frame(const ImageRGB8& colour, const ImageGray8& trimap,
                        const ImageGray8& alpha) {
  const int w = colour.width(), h = colour.height();
  EvalFrame f{colour, DepthImage(w, h), ImageF(w, h, kMattingVirtualMm), ImageF(w, h),
              ImageGray8(w, h)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto t = trimap.at(x, y);
      f.real_depth_mm.at(x, y) = t > 192 ? 500 : t < 64 ? 2000 : 0;
      f.mask.at(x, y) = (t >= 64 && t <= 192) ? 255 : 0;
      f.truth.at(x, y) = 1.0F - alpha.at(x, y) / 255.0F;
    }
  return f;
}

std::vector<EvalCase> alphamatting_cases(const fs::path& root) {
  if (!fs::is_directory(root)) throw ImageFileError(root, "no such dataset directory");
  const fs::path input = root / "input", gt = root / "gt";
  for (const auto& d : {input, gt})
    if (!fs::is_directory(d))
      throw ImageFileError(d, "missing (alphamatting layout: input/, gt/, Trimap*/)");
  std::vector<fs::path> trimap_dirs, images;
  for (const auto& e : fs::directory_iterator(root))
    if (e.is_directory() && e.path().filename().string().rfind("Trimap", 0) == 0)
      trimap_dirs.push_back(e.path());
  for (const auto& e : fs::directory_iterator(input))
    if (e.path().extension() == ".png") images.push_back(e.path());
  std::sort(trimap_dirs.begin(), trimap_dirs.end());
  std::sort(images.begin(), images.end());
  if (trimap_dirs.empty()) throw ImageFileError(root, "no Trimap*/ directory");
  if (images.empty()) throw ImageFileError(input, "no .png image");
  std::vector<EvalCase> cases;
  for (const auto& image : images) {
    const auto colour = read_png_rgb8(image);
    const auto alpha = read_png_gray8(gt / image.filename());
    if (alpha.width() != colour.width() || alpha.height() != colour.height())
      throw ImageFileError(gt / image.filename(), "size differs from the input image");
    for (const auto& tdir : trimap_dirs) {
      const fs::path tpath = tdir / image.filename();
      if (!fs::exists(tpath)) continue;
      const auto trimap = read_png_gray8(tpath);
      if (trimap.width() != colour.width() || trimap.height() != colour.height())
        throw ImageFileError(tpath, "size differs from the input image");
      EvalCase c;
      c.name = image.stem().string() + "/" + tdir.filename().string();
      c.report_sad = true;
      c.frames.push_back(matting_frame(colour, trimap, alpha));
      cases.push_back(std::move(c));
    }
  }
  if (cases.empty()) throw ImageFileError(root, "no image has a trimap");
  return cases;
}

}  // namespace probeless::eval
