#pragma once
// The Lambert material: base colour, one fixed directional light plus ambient. The
// placeholder until the image-based materials are wired in (and the default), so that the
// pipeline shows shapes without a light model. Vertex shader and fragment prelude: common.hpp.
#include <string_view>

namespace probeless::render::shaders {

inline constexpr std::string_view lambert_fragment = R"GLSL(
uniform vec3 u_light_dir_world;  // unit, pointing towards the light
uniform float u_ambient;         // share of the light that comes from everywhere

void main() {
  float diffuse = max(dot(surface_normal(), u_light_dir_world), 0.0);
  o_colour = encode(albedo() * (u_ambient + (1.0 - u_ambient) * diffuse));
  o_depth_mm = v_depth_mm;
}
)GLSL";

}  // namespace probeless::render::shaders
