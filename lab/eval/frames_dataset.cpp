#include "lab/eval/frames_dataset.hpp"

#include <algorithm>
#include <set>

#include "drivers/io/pfm.hpp"
#include "drivers/io/png.hpp"

namespace probeless::eval {
namespace fs = std::filesystem;
namespace {

constexpr const char* kColourSuffix = "_color.png";

// Frame ids: the NNNNNN of every NNNNNN_color.png, sorted.
std::vector<std::string> frame_ids(const fs::path& dir) {
  std::set<std::string> ids;
  const std::string suffix = kColourSuffix;
  for (const auto& e : fs::directory_iterator(dir)) {
    const auto name = e.path().filename().string();
    if (name.size() > suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      ids.insert(name.substr(0, name.size() - suffix.size()));
  }
  return {ids.begin(), ids.end()};
}

EvalCase load_sequence(const fs::path& dir, const std::vector<std::string>& ids) {
  EvalCase c;
  c.name = dir.filename().string();
  for (const auto& id : ids) {
    EvalFrame f;
    f.colour = read_png_rgb8(dir / (id + kColourSuffix));
    f.real_depth_mm = read_png_depth16(dir / (id + "_depth.png"));
    f.virtual_depth_mm = read_pfm(dir / (id + "_virtual_depth.pfm"));
    const auto matte = read_png_gray8(dir / (id + "_matte.png"));
    const int w = f.colour.width(), h = f.colour.height();
    auto check = [&](int iw, int ih, const std::string& file) {
      if (iw != w || ih != h)
        throw ImageFileError(dir / file, "size differs from the colour frame");
    };
    check(f.real_depth_mm.width(), f.real_depth_mm.height(), id + "_depth.png");
    check(f.virtual_depth_mm.width(), f.virtual_depth_mm.height(), id + "_virtual_depth.pfm");
    check(matte.width(), matte.height(), id + "_matte.png");
    f.truth = ImageF(w, h);
    for (std::size_t i = 0; i < matte.pixel_count(); ++i)
      f.truth.data()[i] = matte.data()[i] / 255.0F;
    const fs::path mask_path = dir / (id + "_mask.png");
    if (fs::exists(mask_path)) {
      f.mask = read_png_gray8(mask_path);
      check(f.mask.width(), f.mask.height(), id + "_mask.png");
    } else {
      f.mask = ImageGray8(w, h);
      for (std::size_t i = 0; i < f.mask.pixel_count(); ++i)
        f.mask.data()[i] = f.virtual_depth_mm.data()[i] > 0 ? 255 : 0;
    }
    c.frames.push_back(std::move(f));
  }
  return c;
}

}  // namespace

std::vector<EvalCase> recorded_cases(const fs::path& root) {
  if (!fs::is_directory(root)) throw ImageFileError(root, "no such dataset directory");
  std::vector<EvalCase> cases;
  if (auto ids = frame_ids(root); !ids.empty()) {
    cases.push_back(load_sequence(root, ids));
    return cases;
  }
  std::vector<fs::path> dirs;
  for (const auto& e : fs::directory_iterator(root))
    if (e.is_directory()) dirs.push_back(e.path());
  std::sort(dirs.begin(), dirs.end());
  for (const auto& d : dirs)
    if (auto ids = frame_ids(d); !ids.empty()) cases.push_back(load_sequence(d, ids));
  if (cases.empty())
    throw ImageFileError(root,
                         "no recorded sequence (NNNNNN_color.png frames) here or one level down");
  return cases;
}

}  // namespace probeless::eval
