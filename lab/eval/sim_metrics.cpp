#include "lab/eval/sim_metrics.hpp"

#include <stdexcept>

#include "lab/eval/matte_metrics.hpp"

namespace probeless::eval {

std::optional<double> windowed_temporal_noise(const std::vector<ImageF>& alphas,
                                              const std::vector<ImageF>& truths,
                                              const std::vector<ImageGray8>& masks, int window) {
  const auto k = static_cast<int>(alphas.size());
  if (window <= 1 || window >= k) return temporal_noise(alphas, truths, masks);
  double sum = 0;
  int n = 0;
  for (int start = 0; start + window <= k; start += window) {
    const auto b = static_cast<std::ptrdiff_t>(start), e = b + window;
    const std::vector<ImageF> a(alphas.begin() + b, alphas.begin() + e),
        t(truths.begin() + b, truths.begin() + e);
    // Only where the truth holds still over the window: a pixel the arm's edge crosses
    // changes its truth, and following that change is what MSE scores, not noise.
    std::vector<ImageGray8> m(masks.begin() + b, masks.begin() + e);
    for (std::size_t i = 0; i < m[0].pixel_count(); ++i)
      for (int f = 1; f < window; ++f)
        if (t[static_cast<std::size_t>(f)].data()[i] != t[0].data()[i]) {
          m[0].data()[i] = 0;
          break;
        }
    if (auto v = temporal_noise(a, t, m)) sum += *v, ++n;
  }
  if (!n) return std::nullopt;
  return sum / n;
}

std::optional<double> fractional_composite_error(const EvalFrame& f, const ImageF& alpha,
                                                 const ImageRGB8& composite) {
  const ImageRGB8& fg = f.true_foreground.empty() ? f.colour : f.true_foreground;
  const int w = f.colour.width(), h = f.colour.height();
  if (alpha.width() != w || alpha.height() != h || composite.width() != w ||
      composite.height() != h || f.virtual_colour.width() != w || f.virtual_colour.height() != h ||
      fg.width() != w || fg.height() != h)
    throw std::invalid_argument("composite error: image sizes differ");
  double sum = 0;
  std::size_t n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float a = alpha.at(x, y);
      if (!f.mask.at(x, y) || !(a > 0.01F && a < 0.99F)) continue;
      const float t = f.truth.at(x, y);
      for (int c = 0; c < 3; ++c) {
        const float want = static_cast<float>(static_cast<int>(t * f.virtual_colour.at(x, y, c) +
                                                               (1.0F - t) * fg.at(x, y, c) + 0.5F));
        const double d = (composite.at(x, y, c) - want) / 255.0;
        sum += d * d;
      }
      n += 3;
    }
  if (!n) return std::nullopt;
  return sum / static_cast<double>(n);
}

CompositeErrors SimComposite::error(const EvalFrame& f, const DeviceImageRGB8& colour,
                                    const DeviceImageF& virtual_depth_mm, const DeviceImageF& alpha,
                                    const ImageF& host_alpha) {
  if (f.virtual_colour.empty()) return {};
  auto& q = ctx_.queue();
  virtual_colour_.resize(ctx_.context(), f.virtual_colour.width(), f.virtual_colour.height());
  virtual_colour_.upload(q, f.virtual_colour);
  foreground_.process(colour, virtual_depth_mm, alpha, estimated_);
  return {score(f, alpha, host_alpha, estimated_), score(f, alpha, host_alpha, colour)};
}

double SimComposite::score(const EvalFrame& f, const DeviceImageF& alpha, const ImageF& host_alpha,
                           const DeviceImageRGB8& real) {
  compositor_.process(real, virtual_colour_, alpha, out_);
  return fractional_composite_error(f, host_alpha, out_.download(ctx_.queue())).value_or(-1);
}

}  // namespace probeless::eval
