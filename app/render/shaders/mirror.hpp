#pragma once
// The ideal mirror (thesis ch. 6, the chrome sphere): the view ray reflected about the normal
// looks up the environment's radiance as captured (level 0). base_colour is the reflectance (1 for
// a perfect mirror, ~0.55-0.65 for chrome), without a Fresnel rise towards grazing: a metal's
// reflectance hardly changes with angle, and a constant is what a light-probe sphere shows.
#include <string_view>

namespace probeless::render::shaders {

inline constexpr std::string_view mirror_fragment = R"GLSL(
void main() {
  vec3 r = reflect(normalize(v_view_world), surface_normal());
  o_colour = encode(albedo() * environment(r));
  o_depth_mm = v_depth_mm;
}
)GLSL";

}  // namespace probeless::render::shaders
