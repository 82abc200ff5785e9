#pragma once
// Internal to the renderer (renderer.cpp draws, renderer_programs.cpp links the materials'
// programs, renderer_resources.cpp uploads meshes and environments): what they share.
#include "app/render/renderer.hpp"

namespace probeless::render {

struct Renderer::GpuMesh {
  std::weak_ptr<const Mesh> source;  // the entry is dropped when the mesh is gone
  GlVertexArray vao;
  GlBuffer vertices, colours, indices, transfer;
  GLsizei index_count = 0;
  Eigen::Vector4f base_colour;
  Eigen::Vector3f lo, hi;  // the mesh's bounds (object frame): the pixels it can cover
};

struct Renderer::GpuEnvironment {
  std::weak_ptr<const Environment> source;  // likewise
  EnvironmentTexture texture;
};

// Vertex attribute locations of shaders/common.hpp and shaders/prt_diffuse.hpp.
inline constexpr GLuint kPosition = 0, kNormal = 1, kColour = 2;
inline constexpr GLuint kTransfer = 3;  // 3..9: six vec4 and a float

struct Renderer::Program {
  GlProgram program;
  // -1 where the material has no such uniform (glUniform* ignores location -1).
  GLint camera_from_object = -1, projection = -1, world_from_object = -1, world_from_camera = -1;
  GLint base_colour = -1, linear_output = -1, exposure = -1;
  GLint light_dir = -1, ambient = -1;                           // Lambert
  GLint environment_scale = -1, max_lod = -1, irradiance = -1;  // image-based
  GLint roughness = -1, ior = -1, light = -1;                   // RoughMetal, Refraction, PRT
  GLint depth_offset_mm = -1;                                   // GroundShadow
};

// Texture units of the image-based materials' samplers.
inline constexpr GLint kEnvironmentUnit = 0, kSplitSumUnit = 1, kSpecularUnit = 2;

// Size of the split-sum table (split_sum.hpp): A and B are smooth, and 32 x 32 with bilinear
// filtering stays within 1e-3 of the integral away from n.v -> 0.
inline constexpr int kSplitSumSize = 32;
// The RG16F table, clamped and bilinear; computed on the CPU (a few milliseconds, once).
GlTexture make_split_sum_texture();

}  // namespace probeless::render
