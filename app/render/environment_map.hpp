#pragma once
// An Environment on the GPU (docs/rendering.md "Environment"): two cube textures.
//  - radiance: the environment as captured (level 0) with its box-filtered mip chain; the
//    mirror and the refraction read level 0, the prefilter reads the chain.
//  - specular: half the radiance's face size; level 0 is the radiance box-filtered once
//    (roughness 0) and level k >= 1 the radiance prefiltered with the GGX lobe of roughness
//    k / (levels - 1), for the rough metal's split sum (Karis 2013). Half size because a
//    lobe of roughness 0.2 is already ~6 degrees wide, two texels of the first prefiltered
//    level of a 128 px keyframe, and the prefilter's cost is proportional to its texels.
// The prefilter is a GL pass (shaders/prefilter.hpp): on a board's GPU it is where such work
// belongs, and on llvmpipe it runs vectorised on the rasteriser's threads. Its cost per light
// update is in docs/performance.md.
//
// Half floats (RGBA16F) because they are filterable and renderable on every GLES 3.2 (and
// ES 3.0 + EXT_color_buffer_float) implementation, where RGBA32F filtering is an extension
// many GPUs lack. Lamps can outshine half's 65504, so the radiance is stored divided by a
// power of two (`scale`), which costs no precision.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "app/render/environment.hpp"
#include "app/render/gl_objects.hpp"
#include "core/cubemap.hpp"

namespace probeless::render {

struct PrefilterConfig {
  // Levels of the specular texture, level k for roughness k / (levels - 1); fewer when the
  // face is too small (a 128 px keyframe gives 64, 32, 16, 8, 4, 2).
  int levels = 6;
  // GGX importance samples per texel of level 1, four times as many per level below (each
  // has a quarter of the texels and a wider lobe), at most 1024 above the horizon. Filtered
  // importance sampling keeps few samples smooth; the error against the exact integral is
  // measured in docs/rendering.md.
  int samples = 32;
  // Added to the mip level each sample reads (Colbert & Krivanek add 1; 0.5 measured better
  // with nearest-mip reads).
  float lod_bias = 0.5f;
};

// The CPU half of uploading an environment: level 0 (negative radiance to 0, divided by the
// power of two `scale` that keeps the brightest texel inside half float) and its box chain
// down to 1 px, each level RGBA half floats, faces stacked as Environment::faces. Pure CPU
// (no GL), so it can be made beside the Environment on another thread.
struct EnvironmentLevels {
  int face_size = 0;
  float scale = 1.f;
  std::vector<std::vector<std::uint16_t>> halves;  // level j: max(n >> j, 1)^2 x 6 x RGBA
};
// Validates `environment` first (Environment::validate's errors). `scratch` holds the float
// chain between calls (a caller that prepares often keeps one).
EnvironmentLevels prepare_levels(const Environment& environment,
                                 std::vector<std::vector<float>>& scratch);
EnvironmentLevels prepare_levels(const Environment& environment);

struct EnvironmentTexture {
  GlTexture radiance;  // GL_TEXTURE_CUBE_MAP, RGBA16F, face_size, full box chain
  GlTexture specular;  // GL_TEXTURE_CUBE_MAP, RGBA16F, face_size / 2, specular_levels
  int face_size = 0;
  int specular_levels = 0;
  float scale = 1.f;  // radiance = texel value x scale (a power of two)
};

// Owns the prefilter pass's program and scratch objects. Make, use and destroy it with its
// GL context current (the Renderer owns one).
class EnvironmentPrefilter {
 public:
  explicit EnvironmentPrefilter(const PrefilterConfig& config = {});

  // Uploads `environment` (validated) into `out`, reallocating it when the face size changes,
  // and prefilters the specular levels. Uses environment.levels when present (made off this
  // thread), else prepares them here. Enqueues GL work and does not wait for it; leaves the
  // framebuffer, program, viewport and texture bindings changed.
  void update(const Environment& environment, EnvironmentTexture& out);

  const PrefilterConfig& config() const { return config_; }

 private:
  struct TapSet {
    GlBuffer buffer;  // uniform block Taps
    int count = 0;
    float weight_scale = 1.f;
  };
  void make_taps(int face_size, int levels);

  PrefilterConfig config_;
  GlProgram program_;
  GLint u_source_ = -1, u_face_ = -1, u_size_ = -1, u_tap_count_ = -1, u_weight_scale_ = -1;
  std::vector<TapSet> taps_;  // per specular level, for taps_for_size_
  int taps_for_size_ = 0;
  GlFramebuffer framebuffer_;
  GlVertexArray empty_vao_;
  std::vector<std::vector<float>> box_;  // prepare_levels' scratch
};

// The importance samples of the GGX lobe with this alpha that the prefilter reads for each
// texel (Hammersley set, those below the horizon dropped): xyz the direction in the texel's
// frame (z = the texel's direction n = v = r), w the source mip level that covers the
// sample's share of the lobe (Colbert & Krivanek) for a source of source_size px faces.
std::vector<Eigen::Vector4f> ggx_taps(float alpha, int samples, int source_size, float lod_bias);

// Float -> half float bits, rounding to nearest even (finite, infinite and NaN inputs).
std::uint16_t half_from_float(float value);

// A level of a texture as radiance (scale applied), for tests and debugging. Blocks.
enum class EnvironmentLayer { Radiance, Specular };
Cubemap read_environment_level(const EnvironmentTexture& texture, EnvironmentLayer layer,
                               int level);

}  // namespace probeless::render
