#pragma once
// Shared set-up of the envmap kernel tests: random converted fisheye images, views and
// keyframe states, and a tolerant comparison (the kernel's atan2 and floor may land on the
// other side of a pixel edge than the host's for a handful of texels).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/envmap/envmap_types.hpp"

namespace probeless::envmap::testing {

// The sim's fisheye looking straight up from a level rig (drivers/sim/sim_rig.cpp).
inline Eigen::Matrix3d upward_R_camera_world() {
  Eigen::Matrix3d r_world_camera;
  r_world_camera << -Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ();
  return r_world_camera.transpose();
}

inline FisheyeView random_view(std::mt19937& rng, int size) {
  std::uniform_real_distribution<double> u(-1, 1), fov(160, 200);
  FisheyeView v;
  v.camera = KannalaBrandtCamera::equidistant(size, fov(rng)).params();
  v.camera.cx += 3 * u(rng);
  v.camera.fy *= 1 + 0.02 * u(rng);
  v.camera.k = {0.02 * u(rng), 0.01 * u(rng), 0.005 * u(rng), 0.001 * u(rng)};
  const Eigen::Quaterniond q(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized());
  v.R_camera_world = q.toRotationMatrix();
  return v;
}

// Radiance over three decades across the image, neighbours within a factor of two (a float
// rounding of the sample position must not swing the result by more than float rounding);
// a tenth of the pixels unusable (quality 0).
inline ImageRGBAF random_image(std::mt19937& rng, int w, int h) {
  std::uniform_real_distribution<float> e(1, 2), q(0.05F, 1), pick(0, 1);
  ImageRGBAF im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float scale =
          std::pow(10.0F, 3.0F * static_cast<float>(x + y) / static_cast<float>(w + h));
      for (int c = 0; c < 3; ++c) im.at(x, y, c) = scale * e(rng);
      im.at(x, y, 3) = pick(rng) < 0.1F ? 0.0F : q(rng);
    }
  return im;
}

// A keyframe state: half the texels observed (alpha = a variance or a quality), half not.
inline ImageRGBAF random_texels(std::mt19937& rng, int n) {
  std::uniform_real_distribution<float> e(-1, 3), a(1e-4F, 0.5F), pick(0, 1);
  ImageRGBAF t = make_texels(n);
  for (int y = 0; y < 6 * n; ++y)
    for (int x = 0; x < n; ++x) {
      for (int c = 0; c < 3; ++c) t.at(x, y, c) = std::pow(10.0F, e(rng));
      t.at(x, y, 3) = pick(rng) < 0.5F ? 0.0F : a(rng);
    }
  return t;
}

inline bool close(float a, float b) {
  return std::abs(a - b) <= 2e-4F * (1.0F + std::abs(b));
}

// Texels (all four channels) that differ beyond float rounding.
inline int count_mismatches(const ImageRGBAF& got, const ImageRGBAF& want) {
  int bad = 0;
  for (int y = 0; y < want.height(); ++y)
    for (int x = 0; x < want.width(); ++x) {
      bool ok = true;
      for (int c = 0; c < 4; ++c) ok = ok && close(got.at(x, y, c), want.at(x, y, c));
      bad += ok ? 0 : 1;
    }
  return bad;
}

}  // namespace probeless::envmap::testing
