#pragma once
// Shadowed diffuse by precomputed radiance transfer (Sloan, Kautz & Snyder 2002; thesis
// ch. 6): per vertex, 25 transfer coefficients T (5 SH bands, object frame, baked with the
// object's self-shadowing, app/render/prt/) dotted with the environment's 25 radiance
// coefficients L turned into the object frame (core sh_rotation):
//   exit radiance = albedo * sum_i T_i L_i.
// The dot product runs per vertex and the result is interpolated (Gouraud), as in the
// thesis: the transfer is only known at the vertices.
#include <string_view>

namespace probeless::render::shaders {

// Locations 3..9: the 25 coefficients as six vec4 and one float (the mesh's buffer, stride
// 25 floats).
inline constexpr std::string_view prt_vertex = R"GLSL(#version 300 es
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_colour;
layout(location = 3) in vec4 a_transfer0;
layout(location = 4) in vec4 a_transfer1;
layout(location = 5) in vec4 a_transfer2;
layout(location = 6) in vec4 a_transfer3;
layout(location = 7) in vec4 a_transfer4;
layout(location = 8) in vec4 a_transfer5;
layout(location = 9) in float a_transfer6;

uniform mat4 u_camera_from_object;
uniform mat4 u_projection;
uniform mat3 u_world_from_object;
uniform mat3 u_world_from_camera;
// L in the object frame, channel c's coefficient i at u_light[7 c + i / 4][i % 4]; the last
// vec4 of each channel holds L_24 and zeros.
uniform vec4 u_light[21];

out vec3 v_normal_world;
out vec3 v_view_world;
out vec4 v_colour;
out float v_depth_mm;
out vec3 v_transferred;  // sum_i T_i L_i per channel

float transfer_dot(int c) {
  int b = 7 * c;
  return dot(a_transfer0, u_light[b]) + dot(a_transfer1, u_light[b + 1]) +
         dot(a_transfer2, u_light[b + 2]) + dot(a_transfer3, u_light[b + 3]) +
         dot(a_transfer4, u_light[b + 4]) + dot(a_transfer5, u_light[b + 5]) +
         a_transfer6 * u_light[b + 6].x;
}

void main() {
  vec4 p = u_camera_from_object * vec4(a_position, 1.0);
  v_depth_mm = p.z * 1000.0;
  v_normal_world = u_world_from_object * a_normal;
  v_view_world = u_world_from_camera * p.xyz;
  v_colour = a_colour;
  v_transferred = vec3(transfer_dot(0), transfer_dot(1), transfer_dot(2));
  gl_Position = u_projection * p;
}
)GLSL";

inline constexpr std::string_view prt_diffuse_fragment = R"GLSL(
in vec3 v_transferred;

void main() {
  o_colour = encode(albedo() * v_transferred);
  o_depth_mm = v_depth_mm;
}
)GLSL";

// The receiver of differential rendering: the transfer is a difference, so the result is
// signed (no clamp at 0: a shadow is negative) and covers nothing (alpha 0), and the depth is
// pulled towards the camera (Material::depth_offset_mm).
inline constexpr std::string_view ground_shadow_fragment = R"GLSL(
in vec3 v_transferred;
uniform float u_depth_offset_mm;

void main() {
  // The renderer draws it into the float target only; the other branch keeps the uniforms
  // every program has.
  vec3 delta = albedo() * v_transferred;
  o_colour = vec4(u_linear_output ? delta : delta * u_exposure, 0.0);
  o_depth_mm = v_depth_mm - u_depth_offset_mm;
}
)GLSL";

}  // namespace probeless::render::shaders
