#include "core/depth_noise.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace probeless {

namespace {

// splitmix64's finaliser: a counter-based generator, so every dot draws the same numbers
// whatever order or thread computes it.
std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Inverse normal CDF (P. J. Acklam's rational approximation, relative error < 1.2e-9).
double inverse_normal_cdf(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  if (p < 0.02425) {
    const double q = std::sqrt(-2 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  if (p > 1 - 0.02425) return -inverse_normal_cdf(1 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
}

// Standard normal deviates by table lookup on 12 random bits: the 4096 equiprobable
// quantiles, rescaled to unit variance exactly. Tails end at 3.5 sigma; the table (16 KB)
// stays in L1, and a lookup is 20x cheaper than Box-Muller.
class NormalTable {
 public:
  NormalTable() {
    double sum_sq = 0;
    std::array<double, kSize> v;
    for (std::size_t i = 0; i < kSize; ++i) {
      v[i] = inverse_normal_cdf((static_cast<double>(i) + 0.5) / kSize);
      sum_sq += v[i] * v[i];
    }
    const double scale = 1.0 / std::sqrt(sum_sq / kSize);
    for (std::size_t i = 0; i < kSize; ++i) values_[i] = static_cast<float>(v[i] * scale);
  }
  double operator()(std::uint64_t bits) const { return values_[bits & (kSize - 1)]; }

 private:
  static constexpr std::size_t kSize = 4096;
  std::array<float, kSize> values_;
};

const NormalTable& normal_table() {
  static const NormalTable table;
  return table;
}

// Gaussian noise of sigma s (in quanta) added to a value f quanta past a grid point and then
// rounded to the grid gives an output of some variance V(s, f); it is s^2 + 1/12 only on
// average over f (Sheppard), and as much as 7 % off in sigma on a grid point at the model's
// sigma near 3 m. This table inverts V: the s that gives a wanted output sigma t at offset f.
class DitherTable {
 public:
  DitherTable() {
    std::vector<double> v(kS);
    for (int fi = 0; fi < kF; ++fi) {
      const double f = 0.5 * fi / (kF - 1);
      for (int si = 0; si < kS; ++si) {
        v[si] = output_variance(kMaxS * si / (kS - 1), f);
        if (si > 0) v[si] = std::max(v[si], v[si - 1]);  // monotonic for the inversion
      }
      for (int ti = 0; ti < kT; ++ti) {
        const double want = std::pow(kMaxT * ti / (kT - 1), 2);
        int si = 0;
        while (si + 1 < kS && v[si + 1] < want) ++si;
        double s_at = 0;
        if (want > v[0]) {
          const double a = si + 1 < kS ? (want - v[si]) / std::max(v[si + 1] - v[si], 1e-300) : 0.0;
          s_at = kMaxS * (si + std::min(a, 1.0)) / (kS - 1);
        }
        s_[static_cast<std::size_t>(fi) * kT + ti] = s_at;
      }
    }
  }
  // Noise sigma (quanta) for an output sigma t (quanta) at a fractional offset f in [0, 1).
  // Half-way between two quanta the output cannot vary less than +-1/2 quantum; the noise
  // never goes below 0.05 quanta so that such values still round either way at random.
  double noise_for(double t, double f) const { return std::max(lookup(t, f), 0.05); }

 private:
  double lookup(double t, double f) const {
    if (t >= kMaxT) return std::sqrt(t * t - 1.0 / 12.0);  // Sheppard is exact enough here
    const double ff = std::min(f, 1.0 - f) * 2 * (kF - 1), tt = t * (kT - 1) / kMaxT;
    const int fi = std::min(static_cast<int>(ff), kF - 2),
              ti = std::min(static_cast<int>(tt), kT - 2);
    const double a = ff - fi, b = tt - ti;
    const auto at = [&](int i, int j) { return s_[static_cast<std::size_t>(i) * kT + j]; };
    return (1 - a) * ((1 - b) * at(fi, ti) + b * at(fi, ti + 1)) +
           a * ((1 - b) * at(fi + 1, ti) + b * at(fi + 1, ti + 1));
  }

  static constexpr int kF = 33, kT = 129, kS = 481;
  static constexpr double kMaxT = 4.0, kMaxS = 4.8;

  // Variance about its mean of round(f + s n), n standard normal.
  static double output_variance(double s, double f) {
    if (s == 0) return f == 0.5 ? 0.25 : 0.0;
    const auto cdf = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
    const int reach = static_cast<int>(std::ceil(7 * s)) + 1;
    double sum = 0, sum_sq = 0;
    for (int k = -reach; k <= reach + 1; ++k) {
      const double pk = cdf((k + 0.5 - f) / s) - cdf((k - 0.5 - f) / s);
      sum += k * pk;
      sum_sq += static_cast<double>(k) * k * pk;
    }
    return sum_sq - sum * sum;
  }

  std::array<double, static_cast<std::size_t>(kF) * kT> s_{};
};

const DitherTable& dither_table() {
  static const DitherTable table;
  return table;
}

// Nearest integer of a non-negative value (std::round is a library call on baseline x86-64).
double round_positive(double x) {
  return static_cast<double>(static_cast<std::int64_t>(x + 0.5));
}

// The projector's dot pattern: one dot per spacing x spacing cell at a fixed pseudo-random
// offset (a stand-in for the Kinect speckle image simkinect reads). Fixed hardware: it does
// not depend on the seed. With it, what the window rule needs of the geometry: the dots whose
// window fits the image in raster order (simkinect's scan), and each one's neighbours.
struct DotPattern {
  struct Neighbour {
    std::uint32_t dot;
    std::uint32_t r2;  // squared distance to the centre dot, px^2
  };
  std::vector<int> x, y;              // per dot (one per cell, row-major), -1: outside the image
  std::vector<std::uint32_t> scan;    // dots whose window fits, in raster order
  std::vector<std::uint32_t> first;   // per scan entry: its neighbours' start in `neighbours`
  std::vector<Neighbour> neighbours;  // the dots in each window, the centre included

  DotPattern(int width, int height, int spacing, int half) {
    const int cols = (width + spacing - 1) / spacing, rows = (height + spacing - 1) / spacing;
    x.assign(static_cast<std::size_t>(cols) * rows, -1);
    y.assign(x.size(), -1);
    std::vector<std::vector<std::uint32_t>> by_row(height);
    for (int cy = 0; cy < rows; ++cy) {
      for (int cx = 0; cx < cols; ++cx) {
        const std::uint64_t h = mix64(0x5eed0f5eedULL ^ (static_cast<std::uint64_t>(cy) << 32) ^
                                      static_cast<std::uint64_t>(cx));
        const std::size_t k = static_cast<std::size_t>(cy) * cols + cx;
        const int dx = cx * spacing + static_cast<int>(h % spacing);
        const int dy = cy * spacing + static_cast<int>((h >> 32) % spacing);
        if (dx >= width || dy >= height) continue;
        x[k] = dx;
        y[k] = dy;
        if (dx - half >= 0 && dy - half >= 0 && dx + half < width && dy + half < height)
          by_row[dy].push_back(static_cast<std::uint32_t>(k));
      }
    }
    for (const auto& row : by_row) scan.insert(scan.end(), row.begin(), row.end());
    for (std::uint32_t k : scan) {
      first.push_back(static_cast<std::uint32_t>(neighbours.size()));
      const int cx0 = std::max(0, (x[k] - half) / spacing),
                cx1 = std::min(cols - 1, (x[k] + half) / spacing);
      const int cy0 = std::max(0, (y[k] - half) / spacing),
                cy1 = std::min(rows - 1, (y[k] + half) / spacing);
      for (int cy = cy0; cy <= cy1; ++cy) {
        for (int cx = cx0; cx <= cx1; ++cx) {
          const std::size_t j = static_cast<std::size_t>(cy) * cols + cx;
          const int ox = x[j] - x[k], oy = y[j] - y[k];
          if (x[j] < 0 || std::abs(ox) > half || std::abs(oy) > half) continue;
          neighbours.push_back(
              {static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(ox * ox + oy * oy)});
        }
      }
    }
    first.push_back(static_cast<std::uint32_t>(neighbours.size()));
  }
};

// Patterns by image size and window: built once (a few ms), then shared by every call.
std::shared_ptr<const DotPattern> dot_pattern(int width, int height, int spacing, int half) {
  static std::mutex mutex;
  static std::map<std::array<int, 4>, std::shared_ptr<const DotPattern>> cache;
  std::lock_guard lock(mutex);
  auto& entry = cache[{width, height, spacing, half}];
  if (!entry) entry = std::make_shared<const DotPattern>(width, height, spacing, half);
  return entry;
}

}  // namespace

double kinect_axial_sigma_m(double z_m, const KinectNoiseParams& p) {
  const double dz = z_m - p.axial_z0_m;
  return p.axial_a_m + p.axial_b_per_m * dz * dz;
}

DepthImage apply_kinect_noise(const DepthImage& clean, double focal_px, std::uint64_t seed,
                              const KinectNoiseParams& p) {
  if (!(focal_px > 0) || !(p.baseline_m > 0) || !(p.disparity_quantum_px > 0) ||
      p.window_size_px < 1 || p.dot_spacing_px < 1 || p.fill_radius_px < 0)
    throw std::invalid_argument("apply_kinect_noise: invalid focal length or parameters");
  const int w = clean.width(), h = clean.height();
  DepthImage out(w, h, 0);
  if (w == 0 || h == 0) return out;

  const double fb = focal_px * p.baseline_m;
  const double q = p.disparity_quantum_px;
  const double min_mm = p.min_depth_m * 1000, max_mm = p.max_depth_m * 1000;
  const NormalTable& normal = normal_table();
  const DitherTable& dither = dither_table();

  // Clean disparity (0 = invalid) for the window means: simkinect averages the shifted,
  // quantised map, whose window mean differs from the clean one by far less than the rule's
  // tolerance.
  const auto fb_mm = static_cast<float>(fb * 1000.0);
  const auto min_mm_f = static_cast<float>(min_mm), max_mm_f = static_cast<float>(max_mm);
  const auto n_pixels = static_cast<Eigen::Index>(clean.pixel_count());
  std::vector<float> disparity(clean.pixel_count());
  for (std::size_t i = 0; i < disparity.size(); ++i) {
    const float z = clean.data()[i];
    disparity[i] = (z >= min_mm_f && z <= max_mm_f) ? fb_mm / z : 0.0f;
  }

  // Per dot: the shifted, quantised disparity the window rule compares, and the noisy one it
  // outputs. NaN = no valid measurement.
  const int half = p.window_size_px / 2;
  const std::shared_ptr<const DotPattern> pattern = dot_pattern(w, h, p.dot_spacing_px, half);
  const DotPattern& dots = *pattern;
  const float kInvalid = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> rule_d(dots.x.size(), kInvalid), out_d(dots.x.size(), kInvalid);
  for (std::size_t k = 0; k < dots.x.size(); ++k) {
    if (dots.x[k] < 0) continue;
    const int dx = dots.x[k], dy = dots.y[k];
    const std::uint64_t bits = mix64(seed ^ mix64(static_cast<std::uint64_t>(dy) * w + dx));
    // Random 2-D shift with bilinear resampling of the depth (ICL-NUIM). A tap without a
    // surface makes the sample take its nearest tap instead of a blend with nothing.
    const double sx = std::clamp(dx + p.shift_sigma_px * normal(bits), 0.0, w - 1.0);
    const double sy = std::clamp(dy + p.shift_sigma_px * normal(bits >> 12), 0.0, h - 1.0);
    const int x0 = std::max(0, std::min(static_cast<int>(sx), w - 2));
    const int y0 = std::max(0, std::min(static_cast<int>(sy), h - 2));
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const double fx = sx - x0, fy = sy - y0;
    const double z00 = clean.at(x0, y0), z10 = clean.at(x1, y0);
    const double z01 = clean.at(x0, y1), z11 = clean.at(x1, y1);
    double z_mm;
    if (z00 > 0 && z10 > 0 && z01 > 0 && z11 > 0) {
      z_mm = (1 - fy) * ((1 - fx) * z00 + fx * z10) + fy * ((1 - fx) * z01 + fx * z11);
    } else {
      z_mm = clean.at(fx < 0.5 ? x0 : x1, fy < 0.5 ? y0 : y1);
    }
    if (!(z_mm >= min_mm && z_mm <= max_mm)) continue;
    const double z = z_mm / 1000.0;
    const double d = fb / z;
    rule_d[k] = static_cast<float>(round_positive(d / q) * q);
    // The axial noise goes into the disparity before its quantisation, just so much that the
    // quantised output's error has sigma_z(z) in total (less the millimetre rounding's share),
    // wherever d falls between two quanta (docs/sim.md).
    const double ddz = fb / (z * z);  // |d disparity / d z|
    const double sigma_d = kinect_axial_sigma_m(z, p) * ddz;
    const double mm_d = 0.001 * ddz;
    const double target = std::sqrt(std::max(sigma_d * sigma_d - mm_d * mm_d / 12.0, 0.0)) / q;
    const double noise_sigma = q * dither.noise_for(target, d / q - std::floor(d / q));
    const double noisy = d + noise_sigma * normal(bits >> 24);
    if (noisy > 0) out_d[k] = static_cast<float>(round_positive(noisy / q) * q);
  }

  // The window rule (simkinect filterDisp), at dots whose window fits the image, in raster
  // order: survivors claim the pixels around them that no nearer survivor has claimed
  // (weight 1 / (1 + r^2); earlier dots win ties, as in simkinect's scan). Window sums come
  // from per-column sums over the window's rows, slid down the image row by row.
  const int fr = p.fill_radius_px;
  const int fill_side = 2 * fr + 1;
  std::vector<int> fill_run(fill_side);  // half-width of the disc on each row
  std::vector<float> fill_weights(static_cast<std::size_t>(fill_side) * fill_side);  // [dy][dx]
  for (int dy = -fr; dy <= fr; ++dy) {
    fill_run[dy + fr] = static_cast<int>(std::sqrt(static_cast<double>(fr * fr - dy * dy)) + 1e-9);
    for (int dx = -fr; dx <= fr; ++dx)
      fill_weights[static_cast<std::size_t>(dy + fr) * fill_side + dx + fr] =
          1.0f / (1.0f + dx * dx + dy * dy);
  }
  // A dot r px from the centre is an inlier within window_inlier_px * 1.44 r^2 of the mean.
  std::vector<double> tolerance(2 * half * half + 1);
  for (std::size_t r2 = 0; r2 < tolerance.size(); ++r2)
    tolerance[r2] = p.window_inlier_px * (r2 == 0 ? 1.0 : 1.44 * static_cast<double>(r2));
  std::vector<float> fill_weight(clean.pixel_count(), 0.0f);
  std::vector<float> result(clean.pixel_count(), kInvalid);
  std::vector<double> column_sum(w, 0.0);
  std::vector<int> column_count(w, 0);
  const auto add_row = [&](int y, int sign) {
    const float* row = disparity.data() + static_cast<std::size_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      column_sum[x] += sign * row[x];
      column_count[x] += sign * (row[x] > 0);
    }
  };
  int window_row = -1;  // the centre row the column sums are for
  for (std::size_t s = 0; s < dots.scan.size(); ++s) {
    const std::uint32_t k = dots.scan[s];
    const int x = dots.x[k], y = dots.y[k];
    if (std::isnan(rule_d[k]) || std::isnan(out_d[k])) continue;
    if (window_row < 0) {
      for (int r = y - half; r <= y + half; ++r) add_row(r, 1);
      window_row = y;
    }
    for (; window_row < y; ++window_row) {
      add_row(window_row + half + 1, 1);
      add_row(window_row - half, -1);
    }
    double sum = 0;
    int count = 0;
    for (int i = x - half; i <= x + half; ++i) {
      sum += column_sum[i];
      count += column_count[i];
    }
    if (count == 0) continue;
    const double mean = sum / count;
    int n_valid = 0, n_inliers = 0;
    for (std::uint32_t n = dots.first[s]; n < dots.first[s + 1]; ++n) {
      const float d = rule_d[dots.neighbours[n].dot];
      if (std::isnan(d)) continue;
      ++n_valid;
      n_inliers += std::abs(d - mean) < tolerance[dots.neighbours[n].r2];
    }
    const double needed = (dots.first[s + 1] - dots.first[s]) / p.window_valid_ratio;
    if (!(n_valid > needed && n_inliers > needed)) continue;
    const float value = out_d[k];
    for (int dy = -fr; dy <= fr; ++dy) {
      const int py = y + dy;
      if (py < 0 || py >= h) continue;
      const int run = fill_run[dy + fr];
      const int x0 = std::max(x - run, 0), x1 = std::min(x + run, w - 1);
      float* weight_row = fill_weight.data() + static_cast<std::size_t>(py) * w;
      float* result_row = result.data() + static_cast<std::size_t>(py) * w;
      const float* weights = fill_weights.data() + static_cast<std::size_t>(dy + fr) * fill_side;
      for (int px = x0; px <= x1; ++px) {
        const float weight = weights[px - x + fr];
        const bool take = weight_row[px] < weight;
        weight_row[px] = take ? weight : weight_row[px];
        result_row[px] = take ? value : result_row[px];
      }
    }
  }

  // NaN (no measurement) compares false.
  const Eigen::Map<const Eigen::ArrayXf> d_out(result.data(), n_pixels);
  Eigen::Map<Eigen::Array<std::uint16_t, Eigen::Dynamic, 1>>(out.data(), n_pixels) =
      (d_out > 0.0f)
          .select(fb_mm / d_out + 0.5f, 0.0f)
          .min(65535.0f)
          .cast<int>()
          .cast<std::uint16_t>();
  return out;
}

}  // namespace probeless
