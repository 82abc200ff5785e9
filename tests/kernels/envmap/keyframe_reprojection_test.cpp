#include "kernels/envmap/keyframe_reprojection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "envmap_test_support.hpp"
#include "kernels/envmap/envmap_update_reference.hpp"

namespace probeless::envmap {
namespace {

using namespace envmap::testing;

const RoomBox kRoom{{-2.5, -2.5, 0.0}, {2.5, 2.5, 2.7}};

// From the keyframe's own position the reprojection is a box filter of observed-only texels.
TEST(KeyframeReprojection, AtTheKeyframesPositionItIsABoxFilter) {
  std::mt19937 rng(2);
  const int n = 32, m = 8, s = 4;
  ImageRGBAF texels = random_texels(rng, n);
  std::uniform_real_distribution<float> pick(0, 1);
  for (int y = 0; y < 6 * n; ++y)  // 1 % unobserved: some 4 x 4 blocks whole, some not
    for (int x = 0; x < n; ++x) texels.at(x, y, 3) = pick(rng) < 0.01F ? 0.0F : 0.5F;
  const Eigen::Vector3d k(0.3, -0.2, 1.1);
  const ImageRGBAF r = reproject_keyframe(texels, k, kRoom, k, m, s);
  int observed = 0;
  for (int row = 0; row < 6 * m; ++row)
    for (int x = 0; x < m; ++x) {
      const int face = row / m, y = row % m;
      double sum = 0;
      bool all = true;
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) {
          sum += texels.at(x * s + i, face * n + y * s + j, 0);
          all = all && texels.at(x * s + i, face * n + y * s + j, 3) > 0;
        }
      EXPECT_NEAR(r.at(x, row, 0), sum / (s * s), 1e-4 * sum / (s * s)) << x << " " << row;
      EXPECT_EQ(r.at(x, row, 3), all ? 1.0F : 0.0F);
      observed += all ? 1 : 0;
    }
  EXPECT_GT(observed, 6 * m * m / 2);
  EXPECT_LT(observed, 6 * m * m);
}

// A keyframe that holds what its position sees of a painted room, reprojected to a point
// 1.4 m away, shows what that point sees (up to the keyframe's texel size); unobserved
// keyframe texels stay unobserved.
TEST(KeyframeReprojection, ShowsTheRoomFromTheTarget) {
  const int n = 128, m = 32, s = 4;
  const auto paint = [](const Eigen::Vector3f& p) {
    return std::exp(std::sin(1.3F * p.x()) + std::cos(1.7F * p.y()) + 0.4F * p.z());
  };
  const Eigen::Vector3f lo = kRoom.lo.cast<float>(), hi = kRoom.hi.cast<float>();
  const Eigen::Vector3d k(0.0, -1.1, 1.15), target(0.0, 0.6, 0.85);
  ImageRGBAF texels = make_texels(n);
  for (int row = 0; row < 6 * n; ++row)
    for (int x = 0; x < n; ++x) {
      const Eigen::Vector3f d = texel_direction_reference(row / n, x, row % n, n);
      const Eigen::Vector3f kf = k.cast<float>();
      const float v = paint(kf + box_exit(lo - kf, hi - kf, d) * d);
      for (int c = 0; c < 3; ++c) texels.at(x, row, c) = v;
      texels.at(x, row, 3) = row / n == 5 ? 0.0F : 1.0F;  // the floor never observed
    }
  const auto error = [&](const std::optional<RoomBox>& room, int* unobserved_floor) {
    const ImageRGBAF r = reproject_keyframe(texels, k, room, target, m, s);
    double err2 = 0;
    int count = 0;
    *unobserved_floor = 0;
    const Eigen::Vector3f o = target.cast<float>();
    for (int row = 0; row < 6 * m; ++row)
      for (int x = 0; x < m; ++x) {
        const Eigen::Vector3f d = texel_direction_reference(row / m, x, row % m, m);
        const Eigen::Vector3f p = o + box_exit(lo - o, hi - o, d) * d;
        if (p.z() < 1e-4F) *unobserved_floor += r.at(x, row, 3) == 0.0F ? 1 : 0;
        if (r.at(x, row, 3) == 0.0F) continue;
        const double e = r.at(x, row, 0) / paint(p) - 1.0;
        err2 += e * e;
        ++count;
      }
    EXPECT_GT(count, 4 * m * m);
    return std::sqrt(err2 / count);
  };
  int floor_unobserved = 0;
  // Texel quantisation only: 128 px faces, 4 x 4 nearest samples per 32 px texel.
  EXPECT_LT(error(kRoom, &floor_unobserved), 0.03);
  // The floor under the target comes from the keyframe's unobserved floor texels.
  EXPECT_GT(floor_unobserved, m * m / 2);
  EXPECT_GT(error(std::nullopt, &floor_unobserved), 0.15);  // without the box: parallax
}

}  // namespace
}  // namespace probeless::envmap

namespace probeless::envmap {
namespace {

// Only unobserved texels are filled, from the others that observed them, by their mean.
TEST(FillUnobserved, TakesTheMeanOfTheKeyframesThatObservedATexel) {
  ImageRGBAF target = make_texels(4), a = make_texels(4), b = make_texels(4);
  auto set = [](ImageRGBAF& t, int x, int y, float v, float alpha) {
    for (int c = 0; c < 3; ++c) t.at(x, y, c) = v;
    t.at(x, y, 3) = alpha;
  };
  set(target, 0, 0, 9, 1);  // observed: stays
  set(a, 0, 0, 1, 1);
  set(a, 1, 0, 2, 1);  // both observed (1, 0): the mean
  set(b, 1, 0, 4, 1);
  set(b, 2, 0, 6, 0);  // nobody observed (2, 0): unchanged
  set(target, 2, 0, 3, 0);
  EXPECT_EQ(fill_unobserved(target, {&a, &b}), 1);
  EXPECT_EQ(target.at(0, 0, 0), 9);
  EXPECT_FLOAT_EQ(target.at(1, 0, 1), 3);
  EXPECT_EQ(target.at(1, 0, 3), 1);
  EXPECT_EQ(target.at(2, 0, 0), 3);
  EXPECT_EQ(target.at(2, 0, 3), 0);
  ImageRGBAF other_size = make_texels(8);
  EXPECT_THROW(fill_unobserved(target, {&other_size}), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::envmap
