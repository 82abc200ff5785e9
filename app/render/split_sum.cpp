#include "app/render/split_sum.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace probeless::render {
namespace {

float radical_inverse(std::uint32_t bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return static_cast<float>(bits) * 2.3283064365386963e-10f;
}

}  // namespace

Eigen::Vector2f integrate_split_sum(float n_dot_v, float roughness, int samples) {
  constexpr float kPi = std::numbers::pi_v<float>;
  const float alpha = roughness * roughness, a2 = alpha * alpha;
  const float k = alpha / 2;  // Karis: Schlick's k for image-based lighting
  auto g1 = [&](float c) { return c / (c * (1 - k) + k); };
  const Eigen::Vector3f v(std::sqrt(std::max(0.f, 1 - n_dot_v * n_dot_v)), 0.f, n_dot_v);
  double a = 0, b = 0;
  for (int i = 0; i < samples; ++i) {
    const float phi = 2 * kPi * (static_cast<float>(i) + 0.5f) / static_cast<float>(samples);
    const float xi = radical_inverse(static_cast<std::uint32_t>(i));
    const float cos_h = std::sqrt((1 - xi) / (1 + (a2 - 1) * xi));
    const float sin_h = std::sqrt(std::max(0.f, 1 - cos_h * cos_h));
    const Eigen::Vector3f h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
    const float v_dot_h = v.dot(h);
    const Eigen::Vector3f l = 2 * v_dot_h * h - v;
    const float n_dot_l = l.z();
    if (n_dot_l <= 0 || v_dot_h <= 0) continue;
    // BRDF x cos / pdf with pdf = D (n.h) / (4 v.h): the D cancels.
    const float g_vis = g1(n_dot_v) * g1(n_dot_l) * v_dot_h / (cos_h * n_dot_v);
    const float fc = std::pow(1 - v_dot_h, 5.f);
    a += (1 - fc) * g_vis;
    b += fc * g_vis;
  }
  return {static_cast<float>(a / samples), static_cast<float>(b / samples)};
}

std::vector<float> make_split_sum_table(int size, int samples) {
  std::vector<float> t(static_cast<std::size_t>(size) * size * 2);
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const float n_dot_v = (static_cast<float>(i) + 0.5f) / static_cast<float>(size);
      const float roughness = (static_cast<float>(j) + 0.5f) / static_cast<float>(size);
      const Eigen::Vector2f ab = integrate_split_sum(n_dot_v, roughness, samples);
      const auto at = 2 * (static_cast<std::size_t>(j) * size + static_cast<std::size_t>(i));
      t[at] = ab.x();
      t[at + 1] = ab.y();
    }
  return t;
}

Eigen::Vector2f lookup_split_sum(const std::vector<float>& table, int size, float n_dot_v,
                                 float roughness) {
  const float x =
      std::clamp(n_dot_v * static_cast<float>(size) - 0.5f, 0.f, static_cast<float>(size - 1));
  const float y =
      std::clamp(roughness * static_cast<float>(size) - 0.5f, 0.f, static_cast<float>(size - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, size - 1), y1 = std::min(y0 + 1, size - 1);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  auto at = [&](int i, int j) {
    const auto k = 2 * (static_cast<std::size_t>(j) * size + static_cast<std::size_t>(i));
    return Eigen::Vector2f(table[k], table[k + 1]);
  };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
         fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
}

}  // namespace probeless::render
