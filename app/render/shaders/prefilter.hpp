#pragma once
// The GGX prefilter pass (environment_map.cpp): draws one face of one mip level of the
// environment's cube texture. Each texel integrates the environment against the GGX lobe of
// its level's roughness around its own direction, taking n = v = r as Karis does ("Real
// Shading in Unreal Engine 4", 2013: the split sum's first factor), by importance sampling
// the lobe with a Hammersley set. Few samples suffice because each one reads the source's box
// mip chain at the level whose texels cover the sample's share of the lobe (filtered
// importance sampling, Colbert & Krivanek, GPU Gems 3 ch. 20), which trades noise for a
// little extra blur.
#include <string_view>

namespace probeless::render::shaders {

// One triangle that covers the viewport; no vertex buffers.
inline constexpr std::string_view fullscreen_vertex = R"GLSL(#version 300 es
void main() {
  vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)GLSL";

inline constexpr std::string_view prefilter_fragment = R"GLSL(#version 300 es
precision highp float;
precision highp int;

uniform samplerCube u_source;  // the environment at level 0, box-filtered mips below
uniform int u_face;            // 0..5: +X, -X, +Y, -Y, +Z, -Z
uniform float u_size;          // face size of the level being drawn
uniform int u_tap_count;
uniform float u_weight_scale;  // 1 / the sum of the taps' n.l

// The level's importance samples, the same for every texel (environment_map.cpp): xyz the
// light direction in the texel's frame (z along the texel's direction n = v = r), w the
// source mip level that covers the sample's share of the lobe.
layout(std140) uniform Taps {
  vec4 u_taps[1024];
};

layout(location = 0) out vec4 o_colour;

// core/cubemap.cpp's cube_direction: face coordinates (u, v) in [0,1] -> direction, OpenGL
// orientation. Drawing into a face, window row 0 is the face image's row 0 (t = 0).
vec3 cube_direction(int face, vec2 uv) {
  float s = 2.0 * uv.x - 1.0, t = 2.0 * uv.y - 1.0;
  if (face == 0) return normalize(vec3(1.0, -t, -s));
  if (face == 1) return normalize(vec3(-1.0, -t, s));
  if (face == 2) return normalize(vec3(s, 1.0, t));
  if (face == 3) return normalize(vec3(s, -1.0, -t));
  if (face == 4) return normalize(vec3(s, -t, 1.0));
  return normalize(vec3(-s, -t, -1.0));
}

void main() {
  vec3 n = cube_direction(u_face, gl_FragCoord.xy / u_size);
  vec3 up = abs(n.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
  vec3 tx = normalize(cross(up, n));
  vec3 ty = cross(n, tx);
  vec3 sum = vec3(0.0);
  for (int i = 0; i < u_tap_count; ++i) {
    vec4 tap = u_taps[i];
    vec3 l = tx * tap.x + ty * tap.y + n * tap.z;
    sum += textureLod(u_source, l, tap.w).rgb * tap.z;  // weighted by n.l
  }
  o_colour = vec4(sum * u_weight_scale, 1.0);
}
)GLSL";

}  // namespace probeless::render::shaders
