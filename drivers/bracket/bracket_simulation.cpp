#include "drivers/bracket/bracket_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace probeless {
namespace {

double luminance(const float* p) {
  return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(std::min<double>(q * (v.size() - 1) + 0.5, v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

SimulatedCameraModel SimulatedCameraModel::for_bits(int bits) {
  if (bits != 8 && bits != 12) throw std::invalid_argument("simulated camera: 8 or 12 bits");
  SimulatedCameraModel m;
  m.bits = bits;
  // A black pedestal of 1/16 of the range (256 of 4095 as on the IMX477's 12-bit raw), a
  // 10 000 e- full well, read noise of about 3 e- (1.2 DN at 12 bits; 8 bits adds rounding).
  m.black_level = static_cast<std::uint16_t>(1 << (bits - 4));
  m.full_well_e = 10000.0;
  m.read_noise_dn = bits == 8 ? 0.3 : 1.2;
  return m;
}

ImageRGB16 simulate_capture(const ImageRGBF& radiance, const Exposure& exposure,
                            const SimulatedCameraModel& camera, std::mt19937_64& rng) {
  const int full = camera.full_scale();
  const double range = full - camera.black_level;
  const double dn_per_e = exposure.gain() * range / camera.full_well_e;
  const double to_dn = exposure.value() * camera.scale;
  ImageRGB16 raw(radiance.width(), radiance.height());
  std::normal_distribution<double> unit(0.0, 1.0);
  const float* in = radiance.data();
  std::uint16_t* out = raw.data();
  const std::size_t n = radiance.pixel_count() * 3;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = std::max(0.0, static_cast<double>(in[i])) * to_dn;
    // Beyond 4x full scale the noise cannot bring it back: skip the draws.
    if (s > 4.0 * range) {
      out[i] = static_cast<std::uint16_t>(full);
      continue;
    }
    const double sigma = std::sqrt(s * dn_per_e + camera.read_noise_dn * camera.read_noise_dn);
    const double v = std::round(camera.black_level + s + sigma * unit(rng));
    out[i] = static_cast<std::uint16_t>(std::clamp(v, 0.0, static_cast<double>(full)));
  }
  return raw;
}

ImageRGBF merge_bracket(std::span<const BracketFrame> frames, const SimulatedCameraModel& camera,
                        ImageGray8* measured, MergeWeights weights) {
  if (frames.empty()) throw std::invalid_argument("merge_bracket: no frames");
  const int w = frames[0].raw.width(), h = frames[0].raw.height();
  for (const auto& f : frames)
    if (f.raw.width() != w || f.raw.height() != h)
      throw std::invalid_argument("merge_bracket: frame sizes differ");
  const int full = camera.full_scale();
  const double range = full - camera.black_level;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3;

  // One weighted pass; `weight_of(frame, i, x)` gives a usable sample's weight.
  auto merge = [&](auto&& weight_of) {
    std::vector<double> sum(n, 0.0), weight(n, 0.0);
    for (const auto& f : frames) {
      const double inv_e = 1.0 / (f.stamp.exposure.value() * camera.scale);
      const std::uint16_t* p = f.raw.data();
      for (std::size_t i = 0; i < n; ++i) {
        const int v = p[i];
        if (v >= full || v <= camera.black_level) continue;  // saturated or zero: no value
        const double wgt = weight_of(f, i, (v - camera.black_level) / range);
        sum[i] += wgt * (v - camera.black_level) * inv_e;
        weight[i] += wgt;
      }
    }
    for (std::size_t i = 0; i < n; ++i) sum[i] = weight[i] > 0 ? sum[i] / weight[i] : -1.0;
    return sum;  // the estimate, -1 where no sample was usable
  };
  std::vector<double> estimate =
      merge([](const BracketFrame&, std::size_t, double x) { return x < 0.5 ? x : 1.0 - x; });
  if (weights == MergeWeights::NoiseOptimal) {
    const std::vector<double> first = estimate;
    const double read_var = camera.read_noise_dn * camera.read_noise_dn + 1.0 / 12.0;
    estimate = merge([&](const BracketFrame& f, std::size_t i, double) {
      const double ek = f.stamp.exposure.value() * camera.scale;
      const double dn_per_e = f.stamp.exposure.gain() * range / camera.full_well_e;
      const double s = std::max(0.0, first[i]) * ek;
      return ek * ek / (s * dn_per_e + read_var);
    });
  }
  ImageRGBF out(w, h);
  if (measured) *measured = ImageGray8(w, h, 255);
  float* o = out.data();
  for (std::size_t i = 0; i < n; ++i) {
    if (estimate[i] >= 0) {
      o[i] = static_cast<float>(estimate[i]);
    } else if (measured) {
      measured->data()[i / 3] = 0;
    }
  }
  return out;
}

HdrEvalReport evaluate_bracketing(const ImageRGBF& radiance, const HdrEvalOptions& opts) {
  if (radiance.empty()) throw std::invalid_argument("eval hdr: empty image");
  if (opts.cycles < 2) throw std::invalid_argument("eval hdr: at least 2 cycles");
  if (opts.merge_cycles < 1 || opts.merge_cycles >= opts.cycles)
    throw std::invalid_argument("eval hdr: merge cycles must be in [1, cycles)");
  HdrEvalReport r;
  r.bits = opts.bits;
  r.merge_cycles = opts.merge_cycles;
  r.weights = opts.weights;
  SimulatedCameraModel camera = SimulatedCameraModel::for_bits(opts.bits);
  if (opts.full_well_e > 0) camera.full_well_e = opts.full_well_e;
  if (opts.read_noise_dn >= 0) camera.read_noise_dn = opts.read_noise_dn;

  const std::size_t n = radiance.pixel_count();
  std::vector<double> lum;
  lum.reserve(n);
  double lmin = 0, lmax = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double y = luminance(radiance.data() + 3 * i);
    if (y <= 0) continue;
    lum.push_back(y);
    lmin = lmin == 0 ? y : std::min(lmin, y);
    lmax = std::max(lmax, y);
  }
  if (lum.empty()) throw std::invalid_argument("eval hdr: image is black");
  r.scene_range = lmax / lmin;
  // The camera's own auto-exposure hands over with the median at ~18 % of the range.
  const double median = quantile(lum, 0.5);
  camera.scale = opts.median_fraction_of_full * (camera.full_scale() - camera.black_level) /
                 (median * opts.sequencer.initial_exposure);

  // The counts know the camera's noise, as a driver knows its sensor's (docs/bracketing.md).
  const double range = camera.full_scale() - camera.black_level;
  auto full_scale_noise = [&](const Exposure& e) {
    return std::sqrt(range * range * e.gain() / camera.full_well_e +
                     camera.read_noise_dn * camera.read_noise_dn);
  };
  BracketSequencer seq(opts.sequencer);
  std::mt19937_64 rng(opts.seed);
  std::vector<BracketFrame> last;
  int stops_at[3] = {seq.low_stop(), seq.medium_stop(), seq.high_stop()};
  int settle = 0;
  for (int c = 0; c < opts.cycles; ++c) {
    const int now[3] = {seq.low_stop(), seq.medium_stop(), seq.high_stop()};
    if (!std::equal(now, now + 3, stops_at)) {
      settle = c;
      std::copy(now, now + 3, stops_at);
    }
    for (int k = 0; k < 4; ++k) {  // L, M, H, M
      BracketFrame f;
      f.stamp = seq.next();
      f.raw = simulate_capture(radiance, f.stamp.exposure, camera, rng);
      seq.observe(f.stamp,
                  count_exposure(f.raw, camera.bits, camera.black_level, camera.read_noise_dn,
                                 full_scale_noise(f.stamp.exposure)));
      if (c >= opts.cycles - opts.merge_cycles) last.push_back(std::move(f));
    }
  }
  r.settle_cycles = settle;
  r.settled = settle <= opts.cycles - std::max(1, opts.cycles / 4) &&
              seq.low_stop() == stops_at[0] && seq.medium_stop() == stops_at[1] &&
              seq.high_stop() == stops_at[2];
  r.low_stop = seq.low_stop();
  r.medium_stop = seq.medium_stop();
  r.high_stop = seq.high_stop();
  r.low_exposure = seq.exposure_value(r.low_stop);
  r.medium_exposure = seq.exposure_value(r.medium_stop);
  r.high_exposure = seq.exposure_value(r.high_stop);

  ImageGray8 measured;
  const ImageRGBF merged = merge_bracket(last, camera, &measured, opts.weights);
  std::vector<double> err;
  err.reserve(n);
  std::size_t measurable = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!measured.data()[i]) continue;
    ++measurable;
    const float* t = radiance.data() + 3 * i;
    const float* e = merged.data() + 3 * i;
    double num = 0, den = 0;
    for (int c = 0; c < 3; ++c) {
      num += (double(e[c]) - t[c]) * (double(e[c]) - t[c]);
      den += double(t[c]) * t[c];
    }
    if (den > 0) err.push_back(std::sqrt(num / den));
  }
  r.measurable_fraction = static_cast<double>(measurable) / static_cast<double>(n);
  r.median_rel_error = quantile(err, 0.5);
  r.p95_rel_error = quantile(err, 0.95);
  return r;
}

}  // namespace probeless
