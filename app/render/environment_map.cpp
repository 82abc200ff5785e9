#include "app/render/environment_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string>

#include "app/render/shaders/prefilter.hpp"

namespace probeless::render {
namespace {

// Samples per texel grow four-fold per level (see update()); past this the narrowest
// levels' cost stops mattering anyway.
constexpr int kMaxTaps = 1024;            // the Taps block's size (shaders/prefilter.hpp): 16 KB,
                                          // what every GLES 3.0 guarantees for a uniform block
constexpr float kHalfHeadroom = 32768.f;  // half's largest power of two, below its 65504

int level_count(int face_size, int wanted) {
  int levels = 1;
  while (levels < wanted && (face_size >> levels) >= 1) ++levels;
  return levels;
}

void set_filtering(GLenum min_filter) {
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(min_filter));
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

// One level of six faces, RGBA half floats, faces one after the other.
void upload_level(GLuint texture, int level, int size, const std::uint16_t* texels) {
  glBindTexture(GL_TEXTURE_CUBE_MAP, texture);
  for (int f = 0; f < 6; ++f)
    glTexSubImage2D(static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), level, 0, 0, size,
                    size, GL_RGBA, GL_HALF_FLOAT,
                    texels + static_cast<std::size_t>(f) * size * size * 4);
}

// 2x2 box average of each face (faces do not mix, as glGenerateMipmap's). Odd sizes repeat
// their last row and column.
void box_down(const std::vector<float>& in, int size, std::vector<float>& out) {
  const int half = std::max(size / 2, 1);
  out.resize(static_cast<std::size_t>(half) * half * 6 * 4);
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < half; ++y)
      for (int x = 0; x < half; ++x) {
        const int x0 = std::min(2 * x, size - 1), x1 = std::min(2 * x + 1, size - 1);
        const int y0 = std::min(2 * y, size - 1), y1 = std::min(2 * y + 1, size - 1);
        auto at = [&](int xx, int yy) {
          return (static_cast<std::size_t>(f) * size * size + static_cast<std::size_t>(yy) * size +
                  static_cast<std::size_t>(xx)) *
                 4;
        };
        const std::size_t o = (static_cast<std::size_t>(f) * half * half +
                               static_cast<std::size_t>(y) * half + static_cast<std::size_t>(x)) *
                              4;
        for (std::size_t c = 0; c < 4; ++c)
          out[o + c] = 0.25f * (in[at(x0, y0) + c] + in[at(x1, y0) + c] + in[at(x0, y1) + c] +
                                in[at(x1, y1) + c]);
      }
}

// Van der Corput radical inverse in base 2: the second coordinate of the Hammersley set.
float radical_inverse(std::uint32_t bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return static_cast<float>(bits) * 2.3283064365386963e-10f;
}

void to_half(const std::vector<float>& in, std::vector<std::uint16_t>& out) {
  out.resize(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) out[i] = half_from_float(in[i]);
}

}  // namespace

std::uint16_t half_from_float(float value) {
  // F. Giesen's float_to_half_fast3_rtne: no table, a few integer operations; Eigen's
  // software conversion was a third of the upload's time.
  std::uint32_t x = 0;
  std::memcpy(&x, &value, sizeof x);
  const std::uint32_t sign = x & 0x80000000u;
  x ^= sign;
  std::uint16_t out = 0;
  if (x >= 0x47800000u) {  // beyond half's range, infinity or NaN
    out = x > 0x7f800000u ? 0x7e00 : 0x7c00;
  } else if (x < 0x38800000u) {  // a half denormal or zero: let the FPU round it
    constexpr std::uint32_t kMagicBits = 126u << 23;  // 0.5f
    float magic = 0.f, f = 0.f;
    std::memcpy(&magic, &kMagicBits, sizeof magic);
    std::memcpy(&f, &x, sizeof f);
    f += magic;
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, sizeof bits);
    out = static_cast<std::uint16_t>(bits - kMagicBits);
  } else {
    const std::uint32_t odd = (x >> 13) & 1u;  // round to nearest even
    x += (static_cast<std::uint32_t>(15 - 127) << 23) + 0xfffu + odd;
    out = static_cast<std::uint16_t>(x >> 13);
  }
  return static_cast<std::uint16_t>(out | (sign >> 16));
}

std::vector<Eigen::Vector4f> ggx_taps(float alpha, int samples, int source_size, float lod_bias) {
  constexpr float kPi = std::numbers::pi_v<float>;
  const float a2 = alpha * alpha;
  // Solid angle of one source texel (the cube's average).
  const float texel_solid_angle =
      4.f * kPi / (6.f * static_cast<float>(source_size) * static_cast<float>(source_size));
  std::vector<Eigen::Vector4f> taps;
  for (int i = 0; i < samples; ++i) {
    const float phi = 2.f * kPi * (static_cast<float>(i) + 0.5f) / static_cast<float>(samples);
    const float xi = radical_inverse(static_cast<std::uint32_t>(i));
    const float cos_h = std::sqrt((1.f - xi) / (1.f + (a2 - 1.f) * xi));  // GGX D(h) (n.h)
    const float sin_h = std::sqrt(std::max(0.f, 1.f - cos_h * cos_h));
    const Eigen::Vector3f h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
    const Eigen::Vector3f l = 2.f * cos_h * h - Eigen::Vector3f::UnitZ();  // v = n = z
    if (l.z() <= 0.f) continue;  // below the horizon: weight n.l = 0
    // pdf of l = D(h) (n.h) / (4 v.h) = D(h) / 4 with v = n.
    const float d = cos_h * cos_h * (a2 - 1.f) + 1.f;
    const float pdf = a2 / (kPi * d * d) / 4.f;
    const float sample_solid_angle = 1.f / (static_cast<float>(samples) * pdf);
    const float lod =
        std::max(0.5f * std::log2(sample_solid_angle / texel_solid_angle) + lod_bias, 0.f);
    taps.emplace_back(l.x(), l.y(), l.z(), lod);
  }
  return taps;
}

void EnvironmentPrefilter::make_taps(int face_size, int levels) {
  taps_.resize(static_cast<std::size_t>(levels));
  for (int level = 1; level < levels; ++level) {
    const float roughness = static_cast<float>(level) / static_cast<float>(levels - 1);
    // A level has a quarter of the texels of the one above and a wider lobe, which reads
    // coarser mips, whose per-face box filter is a poor stand-in for the lobe: four times the
    // samples keep the level's cost equal and its error down (docs/rendering.md).
    int samples = std::min(config_.samples << (2 * (level - 1)), 4 * kMaxTaps);
    std::vector<Eigen::Vector4f> taps;
    for (;; samples /= 2) {
      taps = ggx_taps(roughness * roughness, samples, face_size, config_.lod_bias);
      if (static_cast<int>(taps.size()) <= kMaxTaps) break;
    }
    TapSet& set = taps_[static_cast<std::size_t>(level)];
    set.count = static_cast<int>(taps.size());
    float weight = 0.f;
    for (const Eigen::Vector4f& t : taps) weight += t.z();
    set.weight_scale = 1.f / weight;
    taps.resize(kMaxTaps, Eigen::Vector4f::Zero());  // the block's declared size
    if (!set.buffer) set.buffer = make_buffer();
    glBindBuffer(GL_UNIFORM_BUFFER, set.buffer.get());
    glBufferData(GL_UNIFORM_BUFFER, static_cast<GLsizeiptr>(taps.size() * sizeof(Eigen::Vector4f)),
                 taps.data(), GL_STATIC_DRAW);
  }
  glBindBuffer(GL_UNIFORM_BUFFER, 0);
  taps_for_size_ = face_size;
}

EnvironmentPrefilter::EnvironmentPrefilter(const PrefilterConfig& config) : config_(config) {
  if (config_.levels < 1 || config_.samples < 1)
    throw std::invalid_argument("environment prefilter: levels and samples must be >= 1");
  program_ = link_program("prefilter", shaders::fullscreen_vertex, shaders::prefilter_fragment);
  const GLuint id = program_.get();
  u_source_ = glGetUniformLocation(id, "u_source");
  u_face_ = glGetUniformLocation(id, "u_face");
  u_size_ = glGetUniformLocation(id, "u_size");
  u_tap_count_ = glGetUniformLocation(id, "u_tap_count");
  u_weight_scale_ = glGetUniformLocation(id, "u_weight_scale");
  const GLuint block = glGetUniformBlockIndex(id, "Taps");
  if (block == GL_INVALID_INDEX) throw GlError("prefilter shader lacks the Taps block");
  glUniformBlockBinding(id, block, 0);
  framebuffer_ = make_framebuffer();
  empty_vao_ = make_vertex_array();
  check_gl("environment prefilter: setup");
}

EnvironmentLevels prepare_levels(const Environment& environment,
                                 std::vector<std::vector<float>>& box) {
  environment.validate();
  const int n = environment.face_size();
  // Level 0 in float: negative radiance to 0, divided by the power-of-two scale that keeps
  // the brightest texel inside half float. The box chain and the conversion to half are done
  // on the CPU: llvmpipe's glGenerateMipmap and its float -> half upload cost several times
  // more (docs/rendering.md "Speed").
  const float* src = environment.faces.data();
  const std::size_t count = environment.faces.elements().size();
  float peak = 0.f;
  for (std::size_t i = 0; i < count; i += 4)
    for (std::size_t c = 0; c < 3; ++c) peak = std::max(peak, src[i + c]);
  EnvironmentLevels out;
  out.face_size = n;
  out.scale = peak > kHalfHeadroom ? std::exp2(std::ceil(std::log2(peak / kHalfHeadroom))) : 1.f;
  const float inverse = 1.f / out.scale;
  const int chain = level_count(n, 32);  // down to 1 px
  box.resize(static_cast<std::size_t>(chain));
  out.halves.resize(static_cast<std::size_t>(chain));
  box[0].resize(count);
  for (std::size_t i = 0; i < count; i += 4) {
    for (std::size_t c = 0; c < 3; ++c) box[0][i + c] = std::max(src[i + c], 0.f) * inverse;
    box[0][i + 3] = 1.f;
  }
  to_half(box[0], out.halves[0]);
  for (std::size_t j = 1; j < box.size(); ++j) {
    box_down(box[j - 1], std::max(n >> (j - 1), 1), box[j]);
    to_half(box[j], out.halves[j]);
  }
  return out;
}

EnvironmentLevels prepare_levels(const Environment& environment) {
  std::vector<std::vector<float>> scratch;
  return prepare_levels(environment, scratch);
}

void EnvironmentPrefilter::update(const Environment& environment, EnvironmentTexture& out) {
  EnvironmentLevels own;
  const EnvironmentLevels* levels = environment.levels.get();
  if (!levels || levels->face_size != environment.face_size()) {
    own = prepare_levels(environment, box_);
    levels = &own;
  }
  const int n = levels->face_size;
  const int chain = static_cast<int>(levels->halves.size());
  const float scale = levels->scale;

  glActiveTexture(GL_TEXTURE0);  // every bind below is on unit 0
  const int spec_size = std::max(n / 2, 1);
  if (!out.radiance || out.face_size != n) {
    out.face_size = n;
    out.radiance = make_texture();
    glBindTexture(GL_TEXTURE_CUBE_MAP, out.radiance.get());
    glTexStorage2D(GL_TEXTURE_CUBE_MAP, chain, GL_RGBA16F, n, n);
    // Nearest mip, bilinear within it: the prefilter's samples read whole levels (half the
    // fetches of trilinear and, measured, no less accurate); the mirror reads level 0.
    set_filtering(GL_LINEAR_MIPMAP_NEAREST);
    out.specular = make_texture();
    out.specular_levels = level_count(spec_size, config_.levels);
    glBindTexture(GL_TEXTURE_CUBE_MAP, out.specular.get());
    glTexStorage2D(GL_TEXTURE_CUBE_MAP, out.specular_levels, GL_RGBA16F, spec_size, spec_size);
    set_filtering(GL_LINEAR_MIPMAP_LINEAR);  // the rough metal blends between roughnesses
  }
  out.scale = scale;
  for (int j = 0; j < chain; ++j)
    upload_level(out.radiance.get(), j, std::max(n >> j, 1),
                 levels->halves[static_cast<std::size_t>(j)].data());
  upload_level(out.specular.get(), 0, spec_size, levels->halves[n > 1 ? 1 : 0].data());
  if (out.specular_levels == 1) {
    check_gl("environment prefilter: upload");
    return;
  }

  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glUseProgram(program_.get());
  glBindTexture(GL_TEXTURE_CUBE_MAP, out.radiance.get());
  glUniform1i(u_source_, 0);
  if (taps_for_size_ != n) make_taps(n, out.specular_levels);
  glBindVertexArray(empty_vao_.get());
  for (int level = 1; level < out.specular_levels; ++level) {
    const int size = std::max(spec_size >> level, 1);
    const TapSet& taps = taps_[static_cast<std::size_t>(level)];
    glViewport(0, 0, size, size);
    glUniform1f(u_size_, static_cast<float>(size));
    glUniform1i(u_tap_count_, taps.count);
    glUniform1f(u_weight_scale_, taps.weight_scale);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, taps.buffer.get());
    for (int f = 0; f < 6; ++f) {
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                             static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f),
                             out.specular.get(), level);
      glUniform1i(u_face_, f);
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
  }
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
  glBindVertexArray(0);
  check_gl("environment prefilter");
}

Cubemap read_environment_level(const EnvironmentTexture& texture, EnvironmentLayer layer,
                               int level) {
  const bool specular = layer == EnvironmentLayer::Specular;
  const int base = specular ? std::max(texture.face_size / 2, 1) : texture.face_size;
  const int levels = specular ? texture.specular_levels : level_count(texture.face_size, 32);
  const GLuint name = specular ? texture.specular.get() : texture.radiance.get();
  if (name == 0 || level < 0 || level >= levels)
    throw std::invalid_argument("read_environment_level: no such level " + std::to_string(level));
  const int size = std::max(base >> level, 1);
  GlFramebuffer fb = make_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fb.get());
  Cubemap out(size);
  std::vector<float> rgba(static_cast<std::size_t>(size) * size * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  for (int f = 0; f < 6; ++f) {
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                           static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), name, level);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, size, size, GL_RGBA, GL_FLOAT, rgba.data());
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x)
        for (int c = 0; c < 3; ++c)
          out.faces[static_cast<std::size_t>(f)].at(x, y, c) =
              rgba[(static_cast<std::size_t>(y) * size + x) * 4 + c] * texture.scale;
  }
  check_gl("read_environment_level");
  return out;
}

}  // namespace probeless::render
