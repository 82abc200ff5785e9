#pragma once
// Refraction (glass, water): the view ray refracted once, at the front face, by Snell's law
// with index u_ior, and looked up in the environment, mixed with the mirror reflection by the
// exact unpolarised Fresnel reflectance of a dielectric (Walter et al. 2007, eq. 22). The ray
// is not traced through the object: the exit refraction at the back, total internal
// reflection inside and absorption are left out (docs/rendering.md "Limits"). A solid sphere
// still shows the environment upside down, as a real ball lens does, because the front
// refraction alone bends the top of the sphere's view downwards.
// base_colour tints the transmitted light (1 = clear).
#include <string_view>

namespace probeless::render::shaders {

inline constexpr std::string_view refraction_fragment = R"GLSL(
uniform float u_ior;  // of the object relative to the air around it: glass 1.5, water 1.33

// Fresnel reflectance for light arriving at cos_i from the outside.
float fresnel_dielectric(float cos_i, float eta) {
  float g2 = eta * eta - 1.0 + cos_i * cos_i;
  if (g2 < 0.0) return 1.0;  // total internal reflection (eta < 1 only)
  float g = sqrt(g2);
  float a = (g - cos_i) / (g + cos_i);
  float b = (cos_i * (g + cos_i) - 1.0) / (cos_i * (g - cos_i) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

void main() {
  vec3 n = surface_normal();
  vec3 v = normalize(v_view_world);
  float cos_i = clamp(dot(n, -v), 0.0, 1.0);
  float f = fresnel_dielectric(cos_i, u_ior);
  vec3 t = refract(v, n, 1.0 / u_ior);
  vec3 reflected = environment(reflect(v, n));
  vec3 transmitted = environment(t) * albedo();
  o_colour = encode(f * reflected + (1.0 - f) * transmitted);
  o_depth_mm = v_depth_mm;
}
)GLSL";

}  // namespace probeless::render::shaders
