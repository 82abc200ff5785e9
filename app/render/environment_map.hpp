#pragma once
// An Environment on the GPU (docs/rendering.md "Environment"): a cube texture whose level 0
// is the radiance as captured and whose level k >= 1 is the radiance prefiltered with the
// GGX lobe of roughness k / (levels - 1), for the rough metal's split sum (Karis 2013). The
// prefilter is a GL pass (shaders/prefilter.hpp): on llvmpipe it runs vectorised on the
// rasteriser's threads, and on a board's GPU it is where such work belongs; it is cheap
// enough to redo on every light update (docs/performance.md).
//
// Half floats (RGBA16F) because they are filterable and renderable on every GLES 3.2 (and
// ES 3.0 + EXT_color_buffer_float) implementation, where RGBA32F filtering is an extension
// many GPUs lack. Lamps can outshine half's 65504, so the radiance is stored divided by a
// power of two (`scale`), which costs no precision.
#include <vector>

#include "app/render/environment.hpp"
#include "app/render/gl_objects.hpp"
#include "core/cubemap.hpp"

namespace probeless::render {

struct PrefilterConfig {
  // Mip levels, level k prefiltered for roughness k / (levels - 1); fewer when the face is
  // too small (a 128 px face gives 128, 64, 32, 16, 8, 4).
  int levels = 6;
  // GGX importance samples per texel. Filtered importance sampling keeps few samples free of
  // noise; 32 was indistinguishable from 128 within the tests' 3 % (docs/rendering.md).
  int samples = 32;
};

struct EnvironmentTexture {
  GlTexture texture;  // GL_TEXTURE_CUBE_MAP, RGBA16F, `levels` levels
  int face_size = 0;
  int levels = 0;
  float scale = 1.f;  // radiance = texel value x scale (a power of two)
};

// Owns the prefilter pass's program and scratch objects. Make, use and destroy it with its
// GL context current (the Renderer owns one).
class EnvironmentPrefilter {
 public:
  explicit EnvironmentPrefilter(const PrefilterConfig& config = {});

  // Uploads `environment` (validated) into `out`, reallocating it when the face size changes,
  // and prefilters the levels. Enqueues GL work and does not wait for it; leaves the
  // framebuffer, program, viewport and texture bindings changed.
  void update(const Environment& environment, EnvironmentTexture& out);

  const PrefilterConfig& config() const { return config_; }

 private:
  PrefilterConfig config_;
  GlProgram program_;
  GLint u_source_ = -1, u_face_ = -1, u_size_ = -1, u_source_size_ = -1, u_alpha_ = -1,
        u_samples_ = -1;
  GlFramebuffer framebuffer_;
  GlVertexArray empty_vao_;
  GlTexture source_;  // level 0 + box mips, read by the pass
  int source_size_ = 0;
  std::vector<float> staging_;
};

// Level `level` of the texture as radiance (scale applied), for tests and debugging. Blocks.
Cubemap read_environment_level(const EnvironmentTexture& texture, int level);

}  // namespace probeless::render
