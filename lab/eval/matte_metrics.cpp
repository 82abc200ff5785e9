#include "lab/eval/matte_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace probeless::eval {
namespace {

void check_sizes(const ImageF& a, const ImageF& t, const ImageGray8& m) {
  if (a.width() != t.width() || a.height() != t.height() || m.width() != t.width() ||
      m.height() != t.height())
    throw std::invalid_argument("matte metrics: image sizes differ");
}

}  // namespace

std::optional<double> matte_mse(const ImageF& alpha, const ImageF& truth, const ImageGray8& mask) {
  check_sizes(alpha, truth, mask);
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < mask.pixel_count(); ++i)
    if (mask.data()[i]) {
      const double d = double(alpha.data()[i]) - truth.data()[i];
      sum += d * d;
      ++n;
    }
  if (n == 0) return std::nullopt;
  return sum / static_cast<double>(n);
}

double matte_sad(const ImageF& alpha, const ImageF& truth, const ImageGray8& mask) {
  check_sizes(alpha, truth, mask);
  double sum = 0.0;
  for (std::size_t i = 0; i < mask.pixel_count(); ++i)
    if (mask.data()[i]) sum += std::fabs(double(alpha.data()[i]) - truth.data()[i]);
  return sum / 1000.0;
}

ImageGray8 silhouette_band(const ImageF& truth, const ImageGray8& mask, int radius) {
  const int w = truth.width(), h = truth.height();
  ImageGray8 edge(w, h), rows(w, h), band(w, h);
  auto differs = [&](int x, int y, int u, int v) {
    return mask.at(u, v) && std::fabs(truth.at(x, y) - truth.at(u, v)) >= 0.5F;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (mask.at(x, y) &&
          ((x > 0 && differs(x, y, x - 1, y)) || (x + 1 < w && differs(x, y, x + 1, y)) ||
           (y > 0 && differs(x, y, x, y - 1)) || (y + 1 < h && differs(x, y, x, y + 1))))
        edge.at(x, y) = 1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t v = 0;
      for (int k = std::max(0, x - radius); k <= std::min(w - 1, x + radius) && !v; ++k)
        v = edge.at(k, y);
      rows.at(x, y) = v;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t v = 0;
      for (int k = std::max(0, y - radius); k <= std::min(h - 1, y + radius) && !v; ++k)
        v = rows.at(x, k);
      band.at(x, y) = v && mask.at(x, y) ? 255 : 0;
    }
  return band;
}

std::optional<double> temporal_noise(const std::vector<ImageF>& alphas,
                                     const std::vector<ImageF>& truths,
                                     const std::vector<ImageGray8>& masks) {
  const std::size_t k = alphas.size();
  if (k < 2) return std::nullopt;
  if (truths.size() != k || masks.size() != k)
    throw std::invalid_argument("temporal noise: frame counts differ");
  for (std::size_t f = 0; f < k; ++f) check_sizes(alphas[f], truths[f], masks[f]);
  const std::size_t n = alphas[0].pixel_count();
  double total = 0.0;
  std::size_t pixels = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bool all = true;
    for (std::size_t f = 0; f < k && all; ++f) all = masks[f].data()[i] != 0;
    if (!all) continue;
    double mean = 0.0, sq = 0.0;
    for (std::size_t f = 0; f < k; ++f) {
      const double e = double(alphas[f].data()[i]) - truths[f].data()[i];
      mean += e;
      sq += e * e;
    }
    mean /= double(k);
    total += std::max(0.0, sq / double(k) - mean * mean);
    ++pixels;
  }
  if (pixels == 0) return std::nullopt;
  return total / double(pixels);
}

}  // namespace probeless::eval
