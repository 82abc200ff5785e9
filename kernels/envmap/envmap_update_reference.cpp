#include "kernels/envmap/envmap_update_reference.hpp"

#include <algorithm>
#include <cmath>

namespace probeless::envmap {

namespace {

float luminance(const Eigen::Vector4f& v) {
  return 0.2126F * v[0] + 0.7152F * v[1] + 0.0722F * v[2];
}

// envmap_update.cl's polar_angle: atan2(r, z), r >= 0, by Abramowitz & Stegun 4.4.49.
float polar_angle(float r, float z) {
  constexpr float kPi = 3.14159265358979F;
  const float az = std::abs(z);
  const float hi = std::max(r, az), lo = std::min(r, az);
  const float x = hi > 0.0F ? lo / hi : 0.0F, x2 = x * x;
  float a =
      x *
      (1.0F + x2 * (-0.3333314528F +
                    x2 * (0.1999355085F +
                          x2 * (-0.1420889944F +
                                x2 * (0.1065626393F +
                                      x2 * (-0.0752896400F +
                                            x2 * (0.0429096138F +
                                                  x2 * (-0.0161657367F + x2 * 0.0028662257F))))))));
  a = r > az ? 0.5F * kPi - a : a;
  return z < 0.0F ? kPi - a : a;
}

Eigen::Vector4f pixel(const ImageRGBAF& image, int x, int y) {
  return {image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2), image.at(x, y, 3)};
}

}  // namespace

std::optional<Eigen::Vector2f> lut_pixel_reference(const FisheyeLut& lut,
                                                   const Eigen::Vector3f& p) {
  const float r = std::sqrt(p.x() * p.x() + p.y() * p.y());
  const float theta = polar_angle(r, p.z());
  if (!(theta <= lut.max_theta)) return std::nullopt;
  float gx = lut.centre, gy = lut.centre;
  if (r == 0.0F) {
    if (!(p.z() > 0.0F)) return std::nullopt;
  } else {
    const float s = lut.scale * theta / r;
    gx = lut.centre + s * p.x();
    gy = lut.centre + s * p.y();
  }
  const float gx0 = std::floor(gx), gy0 = std::floor(gy);
  if (!(gx0 >= 0.0F && gy0 >= 0.0F && gx0 + 1.0F < static_cast<float>(lut.size) &&
        gy0 + 1.0F < static_cast<float>(lut.size)))
    return std::nullopt;
  const int i = static_cast<int>(gx0), j = static_cast<int>(gy0);
  const auto cell = [&](int di, int dj) {
    return Eigen::Vector2f(lut.pixel.at(i + di, j + dj, 0), lut.pixel.at(i + di, j + dj, 1));
  };
  const Eigen::Vector2f a = cell(0, 0), b = cell(1, 0), c = cell(0, 1), d = cell(1, 1);
  constexpr float kValidAbove = FisheyeLut::kInvalid / 10;  // envmap_update.cl's LUT_VALID_ABOVE
  if (!(a.x() > kValidAbove && b.x() > kValidAbove && c.x() > kValidAbove && d.x() > kValidAbove))
    return std::nullopt;
  const float bx = gx - gx0, by = gy - gy0;
  Eigen::Vector2f uv;
  for (int k = 0; k < 2; ++k) {
    const float top = a[k] + bx * (b[k] - a[k]);
    uv[k] = top + by * ((c[k] + bx * (d[k] - c[k])) - top);
  }
  return uv;
}

Eigen::Vector3f texel_direction_reference(int face, int x, int y, int n) {
  const float inv_n = 1.0F / static_cast<float>(n);
  const float u = (static_cast<float>(x) + 0.5F) * inv_n,
              v = (static_cast<float>(y) + 0.5F) * inv_n;
  return cube_face_direction(face, u, v);
}

std::optional<Eigen::Vector4f> sample_fisheye_reference(const ImageRGBAF& image,
                                                        const FisheyeView& view,
                                                        const Eigen::Vector3f& world_direction) {
  const Eigen::Matrix3f r = view.R_camera_world.cast<float>();
  const auto& w = world_direction;
  Eigen::Vector3f p;
  for (int i = 0; i < 3; ++i) {  // the kernel's order, one rounding per operation
    const float a = r(i, 0) * w.x(), b = r(i, 1) * w.y(), c = r(i, 2) * w.z();
    p[i] = (a + b) + c;
  }
  const auto uv = lut_pixel_reference(*view.lut, p);
  if (!uv) return std::nullopt;
  const float u = uv->x(), v = uv->y();
  const float fx0 = std::floor(u), fy0 = std::floor(v);
  const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
  if (!(fx0 >= 0.0F && fy0 >= 0.0F && x0 + 1 < image.width() && y0 + 1 < image.height()))
    return std::nullopt;
  const float ax = u - fx0, ay = v - fy0;
  const Eigen::Vector4f a = pixel(image, x0, y0), b = pixel(image, x0 + 1, y0),
                        cc = pixel(image, x0, y0 + 1), d = pixel(image, x0 + 1, y0 + 1);
  if (!(a[3] > 0 && b[3] > 0 && cc[3] > 0 && d[3] > 0)) return std::nullopt;
  const Eigen::Vector4f top = a + ax * (b - a), bottom = cc + ax * (d - cc);
  return Eigen::Vector4f(top + ay * (bottom - top));
}

void envmap_update_reference(const ImageRGBAF& image, const FisheyeView& view,
                             const UpdateParams& params, bool publish, ImageRGBAF& texels,
                             ImageRGBAF& pending) {
  const int n = texels.width();
  const float measurement_var = params.measurement_sigma * params.measurement_sigma;
  const float process_var = params.process_sigma * params.process_sigma;
  const float change2 = params.change_sigma > 0 ? params.change_sigma * params.change_sigma : 0.0F;
  const ParallaxConstants parallax = parallax_constants(view);
  for (int row = 0; row < 6 * n; ++row) {
    const int face = row / n, y = row - face * n;
    for (int x = 0; x < n; ++x) {
      const auto z = sample_fisheye_reference(
          image, view, parallax_direction(parallax, texel_direction_reference(face, x, y, n)));
      float* t = &texels.at(x, row);
      if (params.rule == UpdateRule::Kalman) {
        if (!z) continue;
        const float s = measurement_var / (*z)[3];
        const Eigen::Vector4f cur(t[0], t[1], t[2], t[3]);
        Eigen::Vector4f next(z->x(), z->y(), z->z(), s);
        if (cur[3] > 0.0F) {
          const float cvar = cur[3] + process_var;
          const float lx = std::max(luminance(cur), 1e-30F);
          const float e = (luminance(*z) - lx) / lx;
          if (!(change2 > 0.0F && e * e > change2 * (cvar + s))) {
            const float g = cvar / (cvar + s);
            for (int ch = 0; ch < 3; ++ch) next[ch] = cur[ch] + g * ((*z)[ch] - cur[ch]);
            next[3] = (1.0F - g) * cvar;
          }
        }
        for (int ch = 0; ch < 4; ++ch) t[ch] = next[ch];
      } else {
        float* p = &pending.at(x, row);
        if (z && (*z)[3] > p[3])
          for (int ch = 0; ch < 4; ++ch) p[ch] = (*z)[ch];
        if (publish) {
          if (p[3] > 0.0F)
            for (int ch = 0; ch < 4; ++ch) t[ch] = p[ch];
          for (int ch = 0; ch < 4; ++ch) p[ch] = 0.0F;
        }
      }
    }
  }
}

void envmap_update_raw_reference(const ImageRGB16& raw, int bit_depth, std::uint16_t black_level,
                                 const Exposure& exposure, const HdrConversionParams& hdr,
                                 const FisheyeView& view, const UpdateParams& params, bool publish,
                                 ImageRGBAF& texels, ImageRGBAF& pending) {
  envmap_update_reference(hdr_conversion_reference(raw, bit_depth, black_level, exposure, hdr),
                          view, params, publish, texels, pending);
}

}  // namespace probeless::envmap
