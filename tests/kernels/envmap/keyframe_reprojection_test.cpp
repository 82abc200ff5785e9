#include "kernels/envmap/keyframe_reprojection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
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
  const ImageRGBAF r = reproject_keyframe(texels, k, kRoom, k, m, s, Resampling::Bilinear);
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
    const ImageRGBAF r = reproject_keyframe(texels, k, room, target, m, s, Resampling::Bilinear);
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

// A painted room as a keyframe at k sees it (n px faces, all observed).
ImageRGBAF painted_keyframe(int n, const Eigen::Vector3d& k,
                            const std::function<float(const Eigen::Vector3f&)>& paint) {
  const Eigen::Vector3f lo = kRoom.lo.cast<float>(), hi = kRoom.hi.cast<float>();
  const Eigen::Vector3f kf = k.cast<float>();
  ImageRGBAF texels = make_texels(n);
  for (int row = 0; row < 6 * n; ++row)
    for (int x = 0; x < n; ++x) {
      const Eigen::Vector3f d = texel_direction_reference(row / n, x, row % n, n);
      const float v = paint(kf + box_exit(lo - kf, hi - kf, d) * d);
      for (int c = 0; c < 3; ++c) texels.at(x, row, c) = v;
      texels.at(x, row, 3) = 1.0F;
    }
  return texels;
}

// Catmull-Rom follows smooth light closer than bilinear's tent (why the service uses it:
// the lamps' edges in a chrome sphere), and both give the texels back where the samples fall
// on texel centres.
TEST(KeyframeReprojection, CatmullRomIsCloserThanBilinearOnSmoothLight) {
  const int n = 48;
  const auto paint = [](const Eigen::Vector3f& p) {
    return std::exp(std::sin(2.1F * p.x()) + std::cos(2.3F * p.y()) + 0.6F * p.z());
  };
  const Eigen::Vector3d k(0.0, -1.1, 1.15), target(0.2, 0.5, 0.85);
  const ImageRGBAF texels = painted_keyframe(n, k, paint);
  const ReprojectionMap map(n, k, kRoom, target, n, 1);
  const auto error = [&](Resampling resampling) {
    const ImageRGBAF r = map.apply(texels, resampling);
    const Eigen::Vector3f lo = kRoom.lo.cast<float>(), hi = kRoom.hi.cast<float>();
    const Eigen::Vector3f o = target.cast<float>();
    double err2 = 0;
    for (int row = 0; row < 6 * n; ++row)
      for (int x = 0; x < n; ++x) {
        const Eigen::Vector3f d = texel_direction_reference(row / n, x, row % n, n);
        const double e = r.at(x, row, 0) / paint(o + box_exit(lo - o, hi - o, d) * d) - 1.0;
        err2 += e * e;
      }
    return std::sqrt(err2 / (6 * n * n));
  };
  const double bilinear = error(Resampling::Bilinear), catmull_rom = error(Resampling::CatmullRom);
  EXPECT_LT(catmull_rom, 0.8 * bilinear) << bilinear;

  const ImageRGBAF same =
      ReprojectionMap(n, k, kRoom, k, n, 1).apply(texels, Resampling::CatmullRom);
  for (int row = 0; row < 6 * n; row += 7)
    for (int x = 0; x < n; x += 5)
      EXPECT_NEAR(same.at(x, row, 1), texels.at(x, row, 1), 1e-3 * texels.at(x, row, 1));
}

// A lamp 1000 times its ceiling: Catmull-Rom alone would undershoot below the ceiling (even
// below zero) and overshoot above the lamp beside the edge; the clamp to the four nearest
// texels keeps every value between them, and the edge is still sampled in between.
TEST(KeyframeReprojection, CatmullRomDoesNotRingAroundALamp) {
  const int n = 32;
  const auto paint = [](const Eigen::Vector3f& p) {
    const bool lamp = p.z() > 2.69F && std::abs(p.x() - 0.3F) < 0.4F && std::abs(p.y()) < 0.4F;
    return lamp ? 1000.0F : 1.0F;
  };
  const Eigen::Vector3d k(0.0, -0.3, 1.2), target(0.13, 0.21, 1.0);
  const ImageRGBAF r = reproject_keyframe(painted_keyframe(n, k, paint), k, kRoom, target, n, 1,
                                          Resampling::CatmullRom);
  int between = 0;
  for (int row = 0; row < 6 * n; ++row)
    for (int x = 0; x < n; ++x) {
      const float v = r.at(x, row, 0);
      EXPECT_GE(v, 1.0F) << x << " " << row;
      EXPECT_LE(v, 1000.0F) << x << " " << row;
      between += v > 2.0F && v < 900.0F ? 1 : 0;
    }
  EXPECT_GT(between, 8);
}

TEST(KeyframeReprojection, RejectsSizesItCannotMap) {
  const Eigen::Vector3d k(0, 0, 1);
  EXPECT_THROW(ReprojectionMap(0, k, kRoom, k, 8, 1), std::invalid_argument);
  EXPECT_THROW(ReprojectionMap(8, k, kRoom, k, 0, 1), std::invalid_argument);
  EXPECT_THROW(ReprojectionMap(8, k, kRoom, k, 8, 0), std::invalid_argument);
  const ReprojectionMap map(8, k, kRoom, k, 8, 1);
  EXPECT_THROW(map.apply(make_texels(16), Resampling::Bilinear), std::invalid_argument);
  EXPECT_THROW(reproject_keyframe(ImageRGBAF(8, 40), k, kRoom, k, 8, 1, Resampling::Bilinear),
               std::invalid_argument);
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
