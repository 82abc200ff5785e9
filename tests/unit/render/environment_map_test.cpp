// The environment's GPU texture: level count, the power-of-two scale for radiance beyond
// half float, and the GGX prefilter against a brute-force CPU integral over every texel.
#include "app/render/environment_map.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <numbers>

#include "material_reference.hpp"

namespace probeless::render {
namespace {

using testing::cubemap_of;
using testing::environment_of;
using EnvironmentMapTest = testing::MaterialFixture;

constexpr double kPi = std::numbers::pi;

Eigen::Vector3d texel(const Cubemap& c, int face, int x, int y) {
  const ImageRGBF& f = c.faces[static_cast<std::size_t>(face)];
  return {f.at(x, y, 0), f.at(x, y, 1), f.at(x, y, 2)};
}

TEST_F(EnvironmentMapTest, ConstantStaysConstantAtEveryLevel) {
  const Eigen::Vector3d sky(0.25, 1.5, 3.0);
  const auto env = environment_of(128, [&](const Eigen::Vector3d&) { return sky; });
  auto check = [&](EnvironmentLayer layer, int level, int size) {
    const Cubemap c = renderer().read_environment(env, layer, level);
    ASSERT_EQ(c.face_size, size);
    double worst = 0;
    for (int f = 0; f < 6; ++f)
      for (int y = 0; y < c.face_size; ++y)
        for (int x = 0; x < c.face_size; ++x)
          worst =
              std::max(worst, ((texel(c, f, x, y) - sky).array() / sky.array()).abs().maxCoeff());
    EXPECT_LT(worst, 1e-3) << "level " << level;
  };
  for (int level = 0; level < 8; ++level) check(EnvironmentLayer::Radiance, level, 128 >> level);
  for (int level = 0; level < 6; ++level) check(EnvironmentLayer::Specular, level, 64 >> level);
  EXPECT_THROW(renderer().read_environment(env, EnvironmentLayer::Specular, 6),
               std::invalid_argument);
}

TEST_F(EnvironmentMapTest, SmallFacesGetFewerLevels) {
  const auto env = environment_of(
      8, [](const Eigen::Vector3d& d) { return Eigen::Vector3d::Constant(1 + d.z()); });
  // Specular: half the face, down to 1 px: 4, 2, 1.
  EXPECT_EQ(renderer().read_environment(env, EnvironmentLayer::Specular, 2).face_size, 1);
  EXPECT_THROW(renderer().read_environment(env, EnvironmentLayer::Specular, 3),
               std::invalid_argument);
}

// Lamps in the capture's units can exceed half float's 65504: the texture holds radiance
// divided by a power of two, and what comes out is the radiance again.
TEST_F(EnvironmentMapTest, RadianceBeyondHalfFloatSurvives) {
  const Eigen::Vector3d lamp(2e5, 5e4, 1.0);
  const auto env = environment_of(16, [&](const Eigen::Vector3d&) { return lamp; });
  for (int level : {0, 2}) {
    const Eigen::Vector3d got =
        texel(renderer().read_environment(env, EnvironmentLayer::Specular, level), 2, 1, 1);
    std::printf("level %d: %g %g %g\n", level, got.x(), got.y(), got.z());
    EXPECT_NEAR(got.x(), lamp.x(), 1e-3 * lamp.x());
    EXPECT_NEAR(got.y(), lamp.y(), 1e-3 * lamp.y());
    EXPECT_NEAR(got.z(), lamp.z(), 2e-3);
  }
}

// The light thread prepares the levels (prepare_levels) beside the Environment; the renderer
// must then upload exactly what it would have made itself, beyond half float too.
TEST_F(EnvironmentMapTest, PreparedLevelsUploadTheSameTextures) {
  const auto sky = [](const Eigen::Vector3d& d) {
    return Eigen::Vector3d(1 + d.z(), 2e5 * std::max(0.0, d.x()), 0.5 + d.y() * d.y());
  };
  const auto plain = environment_of(32, sky);
  auto prepared = std::make_shared<Environment>(*environment_of(32, sky));
  prepared->levels = std::make_shared<const EnvironmentLevels>(prepare_levels(*prepared));
  ASSERT_EQ(prepared->levels->face_size, 32);
  ASSERT_EQ(prepared->levels->halves.size(), 6u);  // 32 .. 1 px
  EXPECT_GT(prepared->levels->scale, 1.f);         // the 2e5 lobe needs the scale
  const std::shared_ptr<const Environment> shared = prepared;
  for (const auto& [layer, level] :
       {std::pair{EnvironmentLayer::Radiance, 0}, std::pair{EnvironmentLayer::Radiance, 3},
        std::pair{EnvironmentLayer::Specular, 0}, std::pair{EnvironmentLayer::Specular, 2}}) {
    const Cubemap a = renderer().read_environment(plain, layer, level);
    const Cubemap b = renderer().read_environment(shared, layer, level);
    ASSERT_EQ(a.face_size, b.face_size);
    for (int f = 0; f < 6; ++f)
      for (int y = 0; y < a.face_size; ++y)
        for (int x = 0; x < a.face_size; ++x)
          ASSERT_EQ(texel(a, f, x, y), texel(b, f, x, y))
              << "layer " << int(layer) << " level " << level << " face " << f;
  }
  // Levels that belong to another face size are not used.
  auto stale = std::make_shared<Environment>(*environment_of(16, sky));
  stale->levels = prepared->levels;
  const std::shared_ptr<const Environment> stale_shared = stale;
  EXPECT_EQ(renderer().read_environment(stale_shared, EnvironmentLayer::Radiance, 0).face_size, 16);
}

// What the prefilter approximates (Karis 2013 with n = v = r): the average of the radiance
// over the GGX lobe's distribution of light directions, weighted by n.l,
//   P(n) = sum L(w) (n.w) pdf(w) dw / sum (n.w) pdf(w) dw,  pdf(w) = D(h) (n.h) / (4 w.h),
// summed here over every texel of the source (no sampling, no mip chain).
Eigen::Vector3d brute_force(const Cubemap& source, const Eigen::Vector3d& n, double alpha) {
  const int s = source.face_size;
  const double a2 = alpha * alpha;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight = 0;
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < s; ++y)
      for (int x = 0; x < s; ++x) {
        const Eigen::Vector3d w =
            cube_direction(static_cast<CubeFace>(f), (x + 0.5) / s, (y + 0.5) / s);
        const double n_dot_w = n.dot(w);
        if (n_dot_w <= 0) continue;
        const Eigen::Vector3d h = (n + w).normalized();
        const double c = n.dot(h), d = c * c * (a2 - 1) + 1;
        const double pdf = a2 / (kPi * d * d) * c / (4 * w.dot(h));
        const double k = n_dot_w * pdf * cube_texel_solid_angle(x, y, s);
        sum += k * texel(source, f, x, y);
        weight += k;
      }
  return sum / weight;
}

// A sun on a dim sky, soft (~13 degrees) and sharp (~2.5 degrees, two texels of the 64 px
// source): every prefiltered level against the brute-force integral, at the level's texels
// from the sun's centre out to 60 degrees away, relative to the level's peak. With the
// default 32 samples at level 1 the measured worst cases are 4.6 % (soft, level 1) and 5.9 %
// (sharp, level 1); 64 samples halve the soft case (docs/rendering.md).
TEST_F(EnvironmentMapTest, GgxPrefilterMatchesBruteForceIntegral) {
  const Eigen::Vector3d sun = Eigen::Vector3d(0.3, -0.4, 0.87).normalized();
  const Eigen::Vector3d side = sun.cross(Eigen::Vector3d::UnitX()).normalized();
  const int n = 64;
  for (const auto& [sharpness, tolerance] : {std::pair{40.0, 0.05}, std::pair{1000.0, 0.065}}) {
    const Cubemap source = cubemap_of(n, [&](const Eigen::Vector3d& d) {
      const double s = std::exp(sharpness * (d.dot(sun) - 1.0));
      return Eigen::Vector3d(0.1 + 50 * s, 0.1 + 30 * s, 0.2 + 10 * s);
    });
    const auto env = std::make_shared<const Environment>(make_environment(source));
    for (int level = 1; level < 6; ++level) {
      const double roughness = level / 5.0, alpha = roughness * roughness;
      const Cubemap got = renderer().read_environment(env, EnvironmentLayer::Specular, level);
      ASSERT_EQ(got.face_size, (n / 2) >> level);
      double worst = 0, peak = 0;
      for (double degrees = 0; degrees <= 60; degrees += 5) {
        const Eigen::Vector3d d = Eigen::AngleAxisd(degrees * kPi / 180, side) * sun;
        // The level's texel that holds d, and its centre's direction.
        const CubeTexel t = cube_texel_from_direction(d);
        const int size = got.face_size;
        const int x = std::min(static_cast<int>(t.u * size), size - 1);
        const int y = std::min(static_cast<int>(t.v * size), size - 1);
        const Eigen::Vector3d centre = cube_direction(t.face, (x + 0.5) / size, (y + 0.5) / size);
        const Eigen::Vector3d want = brute_force(source, centre, alpha);
        const Eigen::Vector3d have = texel(got, static_cast<int>(t.face), x, y);
        worst = std::max(worst, (have - want).cwiseAbs().maxCoeff());
        peak = std::max(peak, want.maxCoeff());
      }
      EXPECT_LT(worst, tolerance * peak)
          << "sharpness " << sharpness << ", level " << level << " (roughness " << roughness << ")";
      RecordProperty("sun_" + std::to_string(static_cast<int>(sharpness)) + "_level_" +
                         std::to_string(level) + "_worst_over_peak",
                     std::to_string(worst / peak));
    }
  }
}

// The CPU half-float conversion the upload uses, against Eigen's (round to nearest even),
// over normal numbers, half denormals, ties and the overflow boundary.
TEST(HalfFloat, MatchesEigen) {
  std::vector<float> values = {0.f,      1.f,           65504.f,        65519.f,
                               65520.f,  1e6f,          6.1e-5f,        3e-8f,
                               2.98e-8f, 1.0009765625f, 1.00048828125f, 1.00146484375f};
  for (float v = 1e-9f; v < 1e5f; v *= 1.0137f) values.push_back(v);
  for (float v : values)
    for (float s : {v, -v}) {
      const auto eigen = Eigen::numext::bit_cast<std::uint16_t>(Eigen::half(s));
      ASSERT_EQ(half_from_float(s), eigen) << s;
    }
  EXPECT_EQ(half_from_float(std::numeric_limits<float>::infinity()), 0x7c00);
  EXPECT_EQ(half_from_float(std::numeric_limits<float>::quiet_NaN()) & 0x7e00, 0x7e00);
}

// The taps: all above the horizon, the narrow lobe's near the axis reading fine levels, the
// wide lobe's spread out reading coarse ones.
TEST(GgxTaps, FollowTheLobe) {
  const auto narrow = ggx_taps(0.04f, 32, 128, 0.5f);
  const auto wide = ggx_taps(1.f, 512, 128, 0.5f);
  EXPECT_EQ(narrow.size(), 32u);                           // nothing falls below the horizon
  EXPECT_NEAR(static_cast<double>(wide.size()), 256, 20);  // half of alpha = 1's do
  double narrow_z = 0, wide_z = 0, narrow_lod = 0, wide_lod = 0;
  for (const auto& t : narrow) {
    ASSERT_NEAR(t.head<3>().norm(), 1.0, 1e-5);
    narrow_z += t.z() / narrow.size();
    narrow_lod += t.w() / narrow.size();
  }
  for (const auto& t : wide) {
    ASSERT_GT(t.z(), 0.f);
    wide_z += t.z() / wide.size();
    wide_lod += t.w() / wide.size();
  }
  EXPECT_GT(narrow_z, 0.99);
  EXPECT_LT(wide_z, 0.8);
  EXPECT_LT(narrow_lod, wide_lod);
}

}  // namespace
}  // namespace probeless::render
