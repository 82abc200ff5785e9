#pragma once
// Unshadowed diffuse: Lambertian albedo under the environment's irradiance from its first 9
// SH coefficients (Ramamoorthi & Hanrahan, "An Efficient Representation for Irradiance
// Environment Maps", SIGGRAPH 2001, eq. 12), exit radiance = albedo E(n) / pi. Per pixel, in
// the world frame (the normal is turned there, so the SH need no rotation). No shadows, not
// even self-shadowing: that is the PRT material's job.
#include <string_view>

namespace probeless::render::shaders {

inline constexpr std::string_view sh_diffuse_fragment = R"GLSL(
void main() {
  o_colour = encode(albedo() * irradiance(surface_normal()) / kPi);
  o_depth_mm = v_depth_mm;
}
)GLSL";

}  // namespace probeless::render::shaders
