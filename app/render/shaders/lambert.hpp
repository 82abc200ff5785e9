#pragma once
// The Lambert material: base colour, one fixed directional light plus ambient. A material is
// one vertex + fragment pair; the image-based lighting materials will sit beside this file
// with the same inputs and outputs, so the renderer's passes and readback stay as they are.
//
// Every material writes the same two outputs: location 0 the display colour (gamma 2.2,
// alpha = coverage) and location 1 the depth along the optical axis in millimetres.
#include <string_view>

namespace probeless::render::shaders {

inline constexpr std::string_view lambert_vertex = R"GLSL(#version 300 es
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_colour;

uniform mat4 u_camera_from_object;  // OpenCV camera frame, metres, object scale included
uniform mat4 u_projection;          // camera frame -> clip space (renderer.cpp)
uniform mat3 u_world_from_object;   // rotation only: normals to the world frame

out vec3 v_normal_world;
out vec4 v_colour;
out float v_depth_mm;

void main() {
  vec4 p = u_camera_from_object * vec4(a_position, 1.0);
  v_depth_mm = p.z * 1000.0;
  v_normal_world = u_world_from_object * a_normal;
  v_colour = a_colour;
  gl_Position = u_projection * p;
}
)GLSL";

inline constexpr std::string_view lambert_fragment = R"GLSL(#version 300 es
precision highp float;

in vec3 v_normal_world;
in vec4 v_colour;
in float v_depth_mm;

uniform vec4 u_base_colour;      // linear RGBA, times the mesh's vertex colour
uniform vec3 u_light_dir_world;  // unit, pointing towards the light
uniform float u_ambient;         // share of the light that comes from everywhere

layout(location = 0) out vec4 o_colour;
layout(location = 1) out float o_depth_mm;

void main() {
  vec3 n = normalize(v_normal_world);
  if (!gl_FrontFacing) n = -n;  // double-sided materials light their back faces too
  float diffuse = max(dot(n, u_light_dir_world), 0.0);
  vec3 albedo = (u_base_colour * v_colour).rgb;
  vec3 radiance = albedo * (u_ambient + (1.0 - u_ambient) * diffuse);
  o_colour = vec4(pow(clamp(radiance, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
  o_depth_mm = v_depth_mm;
}
)GLSL";

}  // namespace probeless::render::shaders
