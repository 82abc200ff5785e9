#pragma once
// Shared set-up of the envmap kernel tests: random converted fisheye images, views and
// keyframe states, and a tolerant comparison (the kernel's atan2 and floor may land on the
// other side of a pixel edge than the host's for a handful of texels).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/camera/kannala_brandt.hpp"
#include "kernels/envmap/envmap_types.hpp"

namespace probeless::envmap::testing {

// The sim's fisheye looking straight up from a level rig (drivers/sim/sim_rig.cpp).
inline Eigen::Matrix3d upward_R_camera_world() {
  Eigen::Matrix3d r_world_camera;
  r_world_camera << -Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ();
  return r_world_camera.transpose();
}

// A room box around the origin and two positions inside it (the keyframe's, the fisheye's up
// to 0.6 m away), as a rig in a living room would see it.
inline void add_random_room(std::mt19937& rng, FisheyeView& view) {
  std::uniform_real_distribution<double> u(-1, 1);
  RoomBox room;
  room.lo = Eigen::Vector3d(-2.5 + 0.5 * u(rng), -2.0 + 0.5 * u(rng), 0.0);
  room.hi = Eigen::Vector3d(2.5 + 0.5 * u(rng), 3.0 + 0.5 * u(rng), 2.7 + 0.2 * u(rng));
  view.room = room;
  view.keyframe_position = Eigen::Vector3d(0.8 * u(rng), 0.8 * u(rng), 1.2 + 0.3 * u(rng));
  view.position = view.keyframe_position + 0.35 * Eigen::Vector3d(u(rng), u(rng), 0.3 * u(rng));
}

// A Kannala-Brandt fisheye of size x height px (height 0: square) with a random field of view,
// centre offset, aspect and distortion.
inline KannalaBrandtCamera random_camera(std::mt19937& rng, int size, int height = 0) {
  std::uniform_real_distribution<double> u(-1, 1), fov(160, 200);
  KannalaBrandtParams p = KannalaBrandtCamera::equidistant(size, fov(rng)).params();
  p.cx += 3 * u(rng);
  p.fy *= 1 + 0.02 * u(rng);
  p.k = {0.02 * u(rng), 0.01 * u(rng), 0.005 * u(rng), 0.001 * u(rng)};
  if (height > 0) p.height = height;
  return KannalaBrandtCamera(p);
}

inline FisheyeView view_of(const CameraModel& camera, const Eigen::Matrix3d& R_camera_world) {
  FisheyeView v;
  v.lut = build_fisheye_lut(camera);
  v.R_camera_world = R_camera_world;
  return v;
}

inline Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  return Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized())
      .toRotationMatrix();
}

inline FisheyeView random_view(std::mt19937& rng, int size, int height = 0) {
  const KannalaBrandtCamera camera = random_camera(rng, size, height);
  return view_of(camera, random_rotation(rng));
}

// A raw 12-bit frame (black level 256) whose signal rises smoothly over a decade across the
// image, with a twentieth of the pixels saturated in one channel and a twentieth black: the
// fused conversion must flag them as the conversion does.
inline ImageRGB16 random_raw(std::mt19937& rng, int w, int h) {
  std::uniform_real_distribution<float> e(1, 1.3F), pick(0, 1);
  ImageRGB16 raw(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float level =
          300.0F * std::pow(10.0F, static_cast<float>(x + y) / static_cast<float>(w + h));
      std::uint16_t* p = &raw.at(x, y, 0);
      for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint16_t>(256 + level * e(rng));
      const float kind = pick(rng);
      if (kind < 0.05F) p[1] = 4095;               // saturated
      if (kind > 0.95F) p[0] = p[1] = p[2] = 257;  // black
    }
  return raw;
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
