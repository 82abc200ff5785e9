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

uniform samplerCube u_source;    // the environment at level 0, box-filtered mips below
uniform int u_face;              // 0..5: +X, -X, +Y, -Y, +Z, -Z
uniform float u_size;            // face size of the level being drawn
uniform float u_source_size;     // face size of the source's level 0
uniform float u_alpha;           // GGX alpha = roughness^2
uniform int u_samples;

layout(location = 0) out vec4 o_colour;

const float kPi = 3.14159265358979;

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

// Van der Corput radical inverse in base 2: the second coordinate of the Hammersley set.
float radical_inverse(uint bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return float(bits) * 2.3283064365386963e-10;
}

void main() {
  vec3 n = cube_direction(u_face, gl_FragCoord.xy / u_size);
  vec3 up = abs(n.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
  vec3 tx = normalize(cross(up, n));
  vec3 ty = cross(n, tx);
  float a2 = u_alpha * u_alpha;
  // Solid angle of one source texel (the cube's average) and of one sample's share.
  float texel_solid_angle = 4.0 * kPi / (6.0 * u_source_size * u_source_size);
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int i = 0; i < u_samples; ++i) {
    float phi = 2.0 * kPi * (float(i) + 0.5) / float(u_samples);
    float xi = radical_inverse(uint(i));
    float cos_h = sqrt((1.0 - xi) / (1.0 + (a2 - 1.0) * xi));  // GGX's D(h) (n.h) inverted
    float sin_h = sqrt(1.0 - cos_h * cos_h);
    vec3 h = tx * (sin_h * cos(phi)) + ty * (sin_h * sin(phi)) + n * cos_h;
    vec3 l = 2.0 * cos_h * h - n;
    float n_dot_l = dot(n, l);
    if (n_dot_l <= 0.0) continue;
    // pdf of l = D(h) (n.h) / (4 v.h) = D(h) / 4 with v = n.
    float d = cos_h * cos_h * (a2 - 1.0) + 1.0;
    float pdf = a2 / (kPi * d * d) / 4.0;
    float sample_solid_angle = 1.0 / (float(u_samples) * pdf);
    float lod = max(0.5 * log2(sample_solid_angle / texel_solid_angle) + 1.0, 0.0);
    sum += textureLod(u_source, l, lod).rgb * n_dot_l;
    weight += n_dot_l;
  }
  o_colour = vec4(sum / max(weight, 1e-6), 1.0);
}
)GLSL";

}  // namespace probeless::render::shaders
