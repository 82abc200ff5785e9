// The image-based materials against CPU references under analytic environments (constant,
// a small sun, a vertical gradient): every rendered pixel of a sphere is compared with the
// value computed from the exact ray-sphere hit. Radiance is read from the float target.
#include <gtest/gtest.h>

#include <numbers>

#include "app/render/split_sum.hpp"
#include "material_reference.hpp"

namespace probeless::render {
namespace {

using testing::compare_sphere;
using testing::environment_of;
using testing::Hit;
using testing::SphereView;
using S = Material::Shading;

constexpr double kPi = std::numbers::pi;

using MaterialTest = testing::MaterialFixture;

const Eigen::Vector3d kSky(0.5, 1.0, 2.0);  // HDR on purpose: blue above 1

std::shared_ptr<const Environment> constant_sky() {
  return environment_of(16, [](const Eigen::Vector3d&) { return kSky; });
}

// Half floats hold 11 significant bits: 1e-3 relative is their rounding; x2 for the sky's
// largest channel, with room.
constexpr double kHalf = 2e-3 * 2.0;

TEST_F(MaterialTest, MirrorUnderConstantSkyShowsTheSkyTimesReflectance) {
  const SphereView view;
  const Eigen::Vector3f chrome(0.6f, 0.55f, 0.5f);
  compare_sphere(
      view, render(view, material(S::Mirror, chrome), constant_sky()),
      [&](const Hit&) { return Eigen::Vector3d(kSky.cwiseProduct(chrome.cast<double>())); }, kHalf,
      "mirror_constant", 0.0);
}

// E = pi L for a constant L, so a Lambertian sphere is albedo x L everywhere, also where a
// directional light would leave it dark.
TEST_F(MaterialTest, ShDiffuseUnderConstantSkyIsAlbedoTimesTheSky) {
  const SphereView view;
  const Eigen::Vector3f albedo(0.8f, 0.5f, 0.25f);
  compare_sphere(
      view, render(view, material(S::ShDiffuse, albedo), constant_sky()),
      [&](const Hit&) { return Eigen::Vector3d(kSky.cwiseProduct(albedo.cast<double>())); }, kHalf,
      "sh_diffuse_constant", 0.0);
}

// A white metal reflects all the light of a constant sky at every roughness: the split sum
// loses some of it (single scattering) and the multiple-scattering term gives it back. A
// coloured metal follows the same formulas with the CPU's split-sum table.
TEST_F(MaterialTest, RoughMetalUnderConstantSky) {
  const SphereView view;
  for (float roughness : {0.0f, 0.3f, 0.7f, 1.0f}) {
    Material white = material(S::RoughMetal);
    white.roughness = roughness;
    compare_sphere(
        view, render(view, white, constant_sky()), [&](const Hit&) { return kSky; }, kHalf,
        "rough_metal_white_" + std::to_string(roughness), 0.0);
  }
  const Eigen::Vector3d gold(1.0, 0.78, 0.34);
  const std::vector<float> table = make_split_sum_table(32);
  Material metal = material(S::RoughMetal, gold.cast<float>());
  metal.roughness = 0.5f;
  const auto c = compare_sphere(
      view, render(view, metal, constant_sky()),
      [&](const Hit& h) {
        const Eigen::Vector2f ab =
            lookup_split_sum(table, 32, static_cast<float>(h.normal.dot(-h.view)), 0.5f);
        const Eigen::Vector3d single = gold * ab.x() + Eigen::Vector3d::Constant(ab.y());
        const double missing = 1 - ab.x() - ab.y();
        const Eigen::Vector3d f_avg = gold + (Eigen::Vector3d::Ones() - gold) / 21;
        const Eigen::Vector3d multiple =
            (single.cwiseProduct(f_avg).array() / (1 - missing * f_avg.array())).matrix() * missing;
        return Eigen::Vector3d((single + multiple).cwiseProduct(kSky));
      },
      0.01, "rough_metal_gold");
  // Facing the camera a rough metal is about the sky times its colour: within 10 % (each
  // extra bounce between microfacets is tinted by F0 again, which darkens the weak channels;
  // Fresnel brightens them towards grazing).
  const ImageRGBAF img = render(view, metal, constant_sky());
  const Eigen::Vector3d centre = testing::rgb(img, 120, 90).cast<double>();
  for (int ch = 0; ch < 3; ++ch)
    EXPECT_NEAR(centre[ch], gold[ch] * kSky[ch], 0.1 * gold[ch] * kSky[ch]) << ch;
  (void)c;
}

// Exact unpolarised Fresnel reflectance of a dielectric for light from outside.
double fresnel(double cos_i, double eta) {
  const double g = std::sqrt(eta * eta - 1 + cos_i * cos_i);
  const double a = (g - cos_i) / (g + cos_i);
  const double b = (cos_i * (g + cos_i) - 1) / (cos_i * (g - cos_i) + 1);
  return 0.5 * a * a * (1 + b * b);
}

// Clear glass in a constant sky is the sky (reflected and transmitted parts add to 1); a
// tint weights only the transmitted part, by 1 - Fresnel.
TEST_F(MaterialTest, RefractionUnderConstantSky) {
  const SphereView view;
  compare_sphere(
      view, render(view, material(S::Refraction), constant_sky()), [&](const Hit&) { return kSky; },
      kHalf, "refraction_constant", 0.0);
  const Eigen::Vector3d tint(0.5, 0.9, 0.2);
  Material water = material(S::Refraction, tint.cast<float>());
  water.ior = 1.33f;
  compare_sphere(
      view, render(view, water, constant_sky()),
      [&](const Hit& h) {
        const double f = fresnel(h.normal.dot(-h.view), 1.33);
        return Eigen::Vector3d((f * Eigen::Vector3d::Ones() + (1 - f) * tint).cwiseProduct(kSky));
      },
      0.01, "refraction_tinted");
}

}  // namespace
}  // namespace probeless::render
