#include "kernels/occlusion/common/guided_filter_reference.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace probeless::occlusion {
namespace {

std::size_t idx(int x, int y, int w) {
  return static_cast<std::size_t>(y) * w + x;
}

// Solves (Sigma + eps U) a = cov for the symmetric 3x3 Sigma = [s0 s1 s2; s1 s3 s4; s2 s4 s5].
void solve_sym3(const double s[6], double eps, const double cov[3], double a[3]) {
  const double m00 = s[0] + eps, m01 = s[1], m02 = s[2];
  const double m11 = s[3] + eps, m12 = s[4], m22 = s[5] + eps;
  const double i00 = m11 * m22 - m12 * m12;
  const double i01 = m02 * m12 - m01 * m22;
  const double i02 = m01 * m12 - m02 * m11;
  const double i11 = m00 * m22 - m02 * m02;
  const double i12 = m01 * m02 - m00 * m12;
  const double i22 = m00 * m11 - m01 * m01;
  const double det = m00 * i00 + m01 * i01 + m02 * i02;
  const double inv = 1.0 / det;
  a[0] = (i00 * cov[0] + i01 * cov[1] + i02 * cov[2]) * inv;
  a[1] = (i01 * cov[0] + i11 * cov[1] + i12 * cov[2]) * inv;
  a[2] = (i02 * cov[0] + i12 * cov[1] + i22 * cov[2]) * inv;
}

// a (3 planes) and b (1 plane) of the filter at one resolution; returns their window means.
std::vector<double> mean_coefficients(const std::vector<double>& guide3,
                                      const std::vector<double>& p, int w, int h, int r,
                                      double eps) {
  const std::size_t n = static_cast<std::size_t>(w) * h;
  // Moments: I (3), p, I*p (3), I I^T (6) = 13 planes.
  std::vector<double> m(13 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const double ir = guide3[i], ig = guide3[n + i], ib = guide3[2 * n + i], pv = p[i];
    m[i] = ir;
    m[n + i] = ig;
    m[2 * n + i] = ib;
    m[3 * n + i] = pv;
    m[4 * n + i] = ir * pv;
    m[5 * n + i] = ig * pv;
    m[6 * n + i] = ib * pv;
    m[7 * n + i] = ir * ir;
    m[8 * n + i] = ir * ig;
    m[9 * n + i] = ir * ib;
    m[10 * n + i] = ig * ig;
    m[11 * n + i] = ig * ib;
    m[12 * n + i] = ib * ib;
  }
  const auto mean = box_mean_planes(m, w, h, 13, r);
  std::vector<double> ab(4 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const double mr = mean[i], mg = mean[n + i], mb = mean[2 * n + i], mp = mean[3 * n + i];
    const double cov[3] = {mean[4 * n + i] - mr * mp, mean[5 * n + i] - mg * mp,
                           mean[6 * n + i] - mb * mp};
    const double s[6] = {mean[7 * n + i] - mr * mr,  mean[8 * n + i] - mr * mg,
                         mean[9 * n + i] - mr * mb,  mean[10 * n + i] - mg * mg,
                         mean[11 * n + i] - mg * mb, mean[12 * n + i] - mb * mb};
    double a[3];
    solve_sym3(s, eps, cov, a);
    ab[i] = a[0];
    ab[n + i] = a[1];
    ab[2 * n + i] = a[2];
    ab[3 * n + i] = mp - a[0] * mr - a[1] * mg - a[2] * mb;
  }
  return box_mean_planes(ab, w, h, 4, r);
}

}  // namespace

std::vector<double> box_mean_planes(const std::vector<double>& planes, int width, int height,
                                    int channels, int radius) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (planes.size() != n * channels) throw std::invalid_argument("box_mean_planes: size");
  std::vector<double> out(planes.size());
  const int iw = width + 1;
  std::vector<double> sat(static_cast<std::size_t>(iw) * (height + 1));
  for (int c = 0; c < channels; ++c) {
    const double* src = planes.data() + c * n;
    std::fill(sat.begin(), sat.begin() + iw, 0.0);
    for (int y = 0; y < height; ++y) {
      double row = 0.0;
      sat[idx(0, y + 1, iw)] = 0.0;
      for (int x = 0; x < width; ++x) {
        row += src[idx(x, y, width)];
        sat[idx(x + 1, y + 1, iw)] = sat[idx(x + 1, y, iw)] + row;
      }
    }
    double* dst = out.data() + c * n;
    for (int y = 0; y < height; ++y) {
      const int y0 = std::max(0, y - radius), y1 = std::min(height, y + radius + 1);
      for (int x = 0; x < width; ++x) {
        const int x0 = std::max(0, x - radius), x1 = std::min(width, x + radius + 1);
        const double sum = sat[idx(x1, y1, iw)] - sat[idx(x0, y1, iw)] - sat[idx(x1, y0, iw)] +
                           sat[idx(x0, y0, iw)];
        dst[idx(x, y, width)] = sum / static_cast<double>((x1 - x0) * (y1 - y0));
      }
    }
  }
  return out;
}

ImageF guided_filter_reference(const ImageRGBF& guide, const ImageF& input,
                               const GuidedFilterParams& params) {
  const int w = guide.width(), h = guide.height();
  if (input.width() != w || input.height() != h)
    throw std::invalid_argument("guided_filter_reference: guide and input sizes differ");
  if (params.radius < 0 || params.subsample < 1)
    throw std::invalid_argument("guided_filter_reference: bad radius or subsample");
  ImageF out(w, h);
  if (w == 0 || h == 0) return out;
  const int s = params.subsample;
  const int wl = (w + s - 1) / s, hl = (h + s - 1) / s;
  const std::size_t nl = static_cast<std::size_t>(wl) * hl;
  // Block averages over the in-image part of each s x s block (identity when s == 1).
  std::vector<double> g(3 * nl, 0.0), p(nl, 0.0), count(nl, 0.0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t l = idx(x / s, y / s, wl);
      for (int c = 0; c < 3; ++c) g[c * nl + l] += guide.at(x, y, c);
      p[l] += input.at(x, y);
      count[l] += 1.0;
    }
  }
  for (std::size_t l = 0; l < nl; ++l) {
    for (int c = 0; c < 3; ++c) g[c * nl + l] /= count[l];
    p[l] /= count[l];
  }
  const int rl = s == 1 ? params.radius
                        : std::max(1, static_cast<int>(std::lround(double(params.radius) / s)));
  const auto ab = mean_coefficients(g, p, wl, hl, rl, params.eps);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double coef[4];
      if (s == 1) {
        for (int c = 0; c < 4; ++c) coef[c] = ab[c * nl + idx(x, y, w)];
      } else {
        const double u = std::clamp((x + 0.5) / s - 0.5, 0.0, double(wl - 1));
        const double v = std::clamp((y + 0.5) / s - 0.5, 0.0, double(hl - 1));
        const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
        const int x1 = std::min(x0 + 1, wl - 1), y1 = std::min(y0 + 1, hl - 1);
        const double tx = u - x0, ty = v - y0;
        for (int c = 0; c < 4; ++c) {
          const double* plane = ab.data() + c * nl;
          const double top = plane[idx(x0, y0, wl)] * (1 - tx) + plane[idx(x1, y0, wl)] * tx;
          const double bot = plane[idx(x0, y1, wl)] * (1 - tx) + plane[idx(x1, y1, wl)] * tx;
          coef[c] = top * (1 - ty) + bot * ty;
        }
      }
      out.at(x, y) = static_cast<float>(coef[0] * guide.at(x, y, 0) + coef[1] * guide.at(x, y, 1) +
                                        coef[2] * guide.at(x, y, 2) + coef[3]);
    }
  }
  return out;
}

ImageRGBF guide_from_rgb8(const ImageRGB8& colour) {
  ImageRGBF out(colour.width(), colour.height());
  auto src = colour.elements();
  auto dst = out.elements();
  for (std::size_t i = 0; i < src.size(); ++i) dst[i] = src[i] / 255.0F;
  return out;
}

}  // namespace probeless::occlusion
