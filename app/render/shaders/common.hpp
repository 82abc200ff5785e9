#pragma once
// What every material shares: the vertex shader (position, normal, colour in; camera-frame
// depth, world-frame normal and view direction out) and the head of every fragment shader
// (its inputs, the two outputs and the colour encoding). A material's fragment shader is
// fragment_prelude + its own main(); renderer.cpp joins them.
//
// Outputs: location 0 the colour (display: gamma 2.2 of radiance x exposure, clamped to
// [0,1]; linear: radiance as it is, for the HDR compositor), alpha = coverage (1); location 1
// the depth along the optical axis in millimetres.
#include <string_view>

namespace probeless::render::shaders {

inline constexpr std::string_view material_vertex = R"GLSL(#version 300 es
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_colour;

uniform mat4 u_camera_from_object;  // OpenCV camera frame, metres, object scale included
uniform mat4 u_projection;          // camera frame -> clip space (renderer.cpp)
uniform mat3 u_world_from_object;   // rotation only: normals to the world frame
uniform mat3 u_world_from_camera;   // rotation only: view rays to the world frame

out vec3 v_normal_world;
out vec3 v_view_world;  // camera -> surface, world frame, not normalised
out vec4 v_colour;
out float v_depth_mm;

void main() {
  vec4 p = u_camera_from_object * vec4(a_position, 1.0);
  v_depth_mm = p.z * 1000.0;
  v_normal_world = u_world_from_object * a_normal;
  // The camera sits at the camera frame's origin, so the point is its own view ray; turning
  // it (not the world position) keeps precision when the world origin is far away.
  v_view_world = u_world_from_camera * p.xyz;
  v_colour = a_colour;
  gl_Position = u_projection * p;
}
)GLSL";

inline constexpr std::string_view fragment_prelude = R"GLSL(#version 300 es
precision highp float;

in vec3 v_normal_world;
in vec3 v_view_world;
in vec4 v_colour;
in float v_depth_mm;

uniform vec4 u_base_colour;   // linear RGBA, times the mesh's vertex colour
uniform bool u_linear_output; // float target: radiance as it is; else display encoding
uniform float u_exposure;     // display encoding only: radiance x exposure before gamma

layout(location = 0) out vec4 o_colour;
layout(location = 1) out float o_depth_mm;

const float kPi = 3.14159265358979;

vec4 encode(vec3 radiance) {
  radiance = max(radiance, vec3(0.0));  // SH ringing can dip below zero
  if (u_linear_output) return vec4(radiance, 1.0);
  return vec4(pow(clamp(radiance * u_exposure, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}

// The shading normal, facing the viewer on back faces of double-sided materials.
vec3 surface_normal() {
  vec3 n = normalize(v_normal_world);
  return gl_FrontFacing ? n : -n;
}

vec3 albedo() { return (u_base_colour * v_colour).rgb; }
)GLSL";

// The environment's cube textures and what the image-based materials share
// (environment_map.hpp). Texel values are radiance / u_environment_scale (a power of two that
// keeps bright lamps inside half float); the specular texture's level k is prefiltered for
// roughness k / u_max_lod.
inline constexpr std::string_view environment_functions = R"GLSL(
uniform samplerCube u_environment;  // the radiance as captured (level 0)
uniform samplerCube u_specular;     // GGX-prefiltered levels
uniform float u_environment_scale;
uniform float u_max_lod;

vec3 environment(vec3 direction) {
  return textureLod(u_environment, direction, 0.0).rgb * u_environment_scale;
}

vec3 specular(vec3 direction, float roughness) {
  return textureLod(u_specular, direction, roughness * u_max_lod).rgb * u_environment_scale;
}

// R&H 2001 eq. 12: irradiance E(n) = (n, 1)^T M (n, 1), one matrix per channel, from the
// first 9 SH coefficients of the environment in the world frame (material_uniforms.cpp).
uniform mat4 u_irradiance[3];

vec3 irradiance(vec3 n) {
  vec4 h = vec4(n, 1.0);
  return vec3(dot(h, u_irradiance[0] * h), dot(h, u_irradiance[1] * h),
              dot(h, u_irradiance[2] * h));
}
)GLSL";

}  // namespace probeless::render::shaders
