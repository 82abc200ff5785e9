#pragma once
// Rough metal with a colour: GGX microfacets (alpha = roughness^2) under the environment by
// Karis's split sum ("Real Shading in Unreal Engine 4", SIGGRAPH 2013): the prefiltered
// environment in the reflected direction (the specular texture's level for the roughness,
// prefiltered with n = v = r, environment_map.hpp) times the directional albedo F0 A + B from a
// small table (split_sum.hpp). Single scattering loses energy at high roughness (a white metal
// under a constant sky would come out darker than the sky), so the multiple-scattering term of
// Fdez-Aguera ("A Multiple-Scattering Microfacet Model for Real-Time Image-based Lighting",
// JCGT 2019) adds it back, lit by the irradiance as that paper does.
// base_colour = F0, the reflectance at normal incidence (gold ~(1.0, 0.78, 0.34)).
#include <string_view>

namespace probeless::render::shaders {

inline constexpr std::string_view rough_metal_fragment = R"GLSL(
uniform float u_roughness;       // perceptual, [0,1]
uniform sampler2D u_split_sum;   // rg = (A, B) at (n.v, roughness), texel centres

void main() {
  vec3 n = surface_normal();
  vec3 v = normalize(v_view_world);  // towards the surface
  float n_dot_v = clamp(dot(n, -v), 1e-4, 1.0);
  float roughness = clamp(u_roughness, 0.0, 1.0);
  vec2 ab = texture(u_split_sum, vec2(n_dot_v, roughness)).rg;
  vec3 f0 = albedo();
  vec3 single = f0 * ab.x + ab.y;                 // F_ss E_ss
  float missing = 1.0 - (ab.x + ab.y);            // E_ms = 1 - E_ss
  vec3 f_avg = f0 + (1.0 - f0) / 21.0;            // cosine-weighted Schlick Fresnel
  vec3 multiple = single * f_avg / (1.0 - missing * f_avg) * missing;
  vec3 specular = specular(reflect(v, n), roughness);
  o_colour = encode(single * specular + multiple * irradiance(n) / kPi);
  o_depth_mm = v_depth_mm;
}
)GLSL";

}  // namespace probeless::render::shaders
