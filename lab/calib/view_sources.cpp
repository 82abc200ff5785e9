#include "lab/calib/view_sources.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "drivers/io/png.hpp"
#include "drivers/replay/recording.hpp"
#include "lab/calib/board_detector.hpp"

namespace probeless::calib {
namespace fs = std::filesystem;

std::vector<fs::path> list_images(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": no such directory");
  static const std::set<std::string> kExtensions{".jpg", ".jpeg", ".png", ".bmp",
                                                 ".tif", ".tiff", ".pgm", ".ppm"};
  std::vector<fs::path> images;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (kExtensions.contains(ext)) images.push_back(entry.path());
  }
  if (images.empty())
    throw std::runtime_error(dir.string() +
                             ": no images in it (.jpg, .jpeg, .png, .bmp, .tif, .pgm, .ppm)");
  std::sort(images.begin(), images.end());
  return images;
}

std::vector<ImagePair> matching_images(const fs::path& rgb_dir, const fs::path& fisheye_dir,
                                       int* unmatched) {
  std::map<std::string, fs::path> fisheye;
  for (const auto& p : list_images(fisheye_dir)) fisheye[p.stem().string()] = p;
  const auto rgb = list_images(rgb_dir);
  std::vector<ImagePair> pairs;
  for (const auto& p : rgb)
    if (const auto it = fisheye.find(p.stem().string()); it != fisheye.end())
      pairs.push_back({it->first, p, it->second});
  if (unmatched) *unmatched = static_cast<int>(rgb.size() + fisheye.size() - 2 * pairs.size());
  if (pairs.empty())
    throw std::runtime_error(fmt::format(
        "no image of {} has the same name as one in {}: the pairs are matched by file name "
        "without extension",
        rgb_dir.string(), fisheye_dir.string()));
  return pairs;
}

ImageGray8 fisheye_gray(const FisheyeFrame& frame) {
  const ImageRGB16& raw = frame.raw;
  ImageGray8 out(raw.width(), raw.height());
  std::vector<float> luma(raw.pixel_count());
  for (std::size_t i = 0; i < luma.size(); ++i) {
    const std::uint16_t* p = raw.data() + 3 * i;
    const float y = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
    luma[i] = std::max(0.0f, y - frame.black_level);
  }
  std::vector<float> sorted = luma;
  const auto k = static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(sorted.size()));
  std::nth_element(sorted.begin(), sorted.begin() + k, sorted.end());
  const float white = std::max(sorted[static_cast<std::size_t>(k)], 1.0f);
  for (std::size_t i = 0; i < luma.size(); ++i)
    out.data()[i] = static_cast<std::uint8_t>(
        std::lround(255.0 * std::pow(std::min(1.0f, luma[i] / white), 1.0 / 2.2)));
  return out;
}

std::vector<StereoImages> recording_pairs(const fs::path& dir, int max_pairs,
                                          double* depth_baseline_m) {
  const auto recording = replay::Recording::open(dir);
  if (depth_baseline_m) *depth_baseline_m = recording->calibration().depth_baseline_m;
  const auto& rgbd = recording->rgbd();
  struct Pair {
    std::size_t rgb, fisheye;
  };
  std::vector<Pair> pairs;
  for (std::size_t f = 0; f < recording->fisheye().size(); ++f) {
    const TimestampNs t = recording->fisheye()[f].timestamp_ns;
    const auto it = std::lower_bound(
        rgbd.begin(), rgbd.end(), t,
        [](const replay::RgbdEntry& e, TimestampNs v) { return e.timestamp_ns < v; });
    std::size_t best = rgbd.size();
    double gap = kMaxPairGapMs * 1e6;
    for (auto c : {it, it == rgbd.begin() ? it : it - 1}) {
      if (c == rgbd.end()) continue;
      const double g = std::abs(static_cast<double>(c->timestamp_ns - t));
      if (g <= gap) gap = g, best = static_cast<std::size_t>(c - rgbd.begin());
    }
    if (best < rgbd.size()) pairs.push_back({best, f});
  }
  if (pairs.empty())
    throw std::runtime_error(fmt::format(
        "{}: no fisheye frame has a colour frame within {} ms (the recording needs both "
        "streams: {} colour, {} fisheye frames)",
        dir.string(), kMaxPairGapMs, rgbd.size(), recording->fisheye().size()));
  const std::size_t count =
      std::min(pairs.size(), static_cast<std::size_t>(std::max(1, max_pairs)));
  std::vector<StereoImages> out;
  for (std::size_t i = 0; i < count; ++i) {
    const Pair& p = pairs[i * pairs.size() / count];
    const replay::FisheyeEntry& fe = recording->fisheye()[p.fisheye];
    FisheyeFrame frame;
    frame.raw = read_png_rgb16(dir / fe.raw);
    frame.bit_depth = fe.bit_depth;
    frame.black_level = fe.black_level;
    out.push_back({fmt::format("frame_{:06d}", fe.sequence),
                   to_gray(read_png_rgb8(dir / rgbd[p.rgb].colour)), fisheye_gray(frame)});
  }
  return out;
}

}  // namespace probeless::calib
