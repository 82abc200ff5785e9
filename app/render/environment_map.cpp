#include "app/render/environment_map.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "app/render/shaders/prefilter.hpp"

namespace probeless::render {
namespace {

constexpr float kHalfHeadroom = 32768.f;  // half's largest power of two, below its 65504

int level_count(int face_size, int wanted) {
  int levels = 1;
  while (levels < wanted && (face_size >> levels) >= 1) ++levels;
  return levels;
}

int full_chain(int face_size) {
  return static_cast<int>(std::floor(std::log2(face_size))) + 1;
}

void set_filtering(GLenum min_filter) {
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(min_filter));
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void upload_level0(GLuint texture, int n, const float* texels) {
  glBindTexture(GL_TEXTURE_CUBE_MAP, texture);
  for (int f = 0; f < 6; ++f)
    glTexSubImage2D(static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), 0, 0, 0, n, n, GL_RGBA,
                    GL_FLOAT, texels + static_cast<std::size_t>(f) * n * n * 4);
}

}  // namespace

EnvironmentPrefilter::EnvironmentPrefilter(const PrefilterConfig& config) : config_(config) {
  if (config_.levels < 1 || config_.samples < 1)
    throw std::invalid_argument("environment prefilter: levels and samples must be >= 1");
  program_ = link_program("prefilter", shaders::fullscreen_vertex, shaders::prefilter_fragment);
  const GLuint id = program_.get();
  u_source_ = glGetUniformLocation(id, "u_source");
  u_face_ = glGetUniformLocation(id, "u_face");
  u_size_ = glGetUniformLocation(id, "u_size");
  u_source_size_ = glGetUniformLocation(id, "u_source_size");
  u_alpha_ = glGetUniformLocation(id, "u_alpha");
  u_samples_ = glGetUniformLocation(id, "u_samples");
  framebuffer_ = make_framebuffer();
  empty_vao_ = make_vertex_array();
  check_gl("environment prefilter: setup");
}

void EnvironmentPrefilter::update(const Environment& environment, EnvironmentTexture& out) {
  environment.validate();
  const int n = environment.face_size();
  // Staging: negative radiance to 0, and the power-of-two scale that keeps the brightest
  // texel inside half float.
  const float* src = environment.faces.data();
  staging_.resize(environment.faces.elements().size());
  float peak = 0.f;
  for (std::size_t i = 0; i < staging_.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c) peak = std::max(peak, src[i + c]);
  const float scale =
      peak > kHalfHeadroom ? std::exp2(std::ceil(std::log2(peak / kHalfHeadroom))) : 1.f;
  const float inverse = 1.f / scale;
  for (std::size_t i = 0; i < staging_.size(); i += 4) {
    for (std::size_t c = 0; c < 3; ++c) staging_[i + c] = std::max(src[i + c], 0.f) * inverse;
    staging_[i + 3] = 1.f;
  }

  glActiveTexture(GL_TEXTURE0);  // every bind below is on unit 0
  if (!out.texture || out.face_size != n) {
    out.texture = make_texture();
    out.face_size = n;
    out.levels = level_count(n, config_.levels);
    glBindTexture(GL_TEXTURE_CUBE_MAP, out.texture.get());
    glTexStorage2D(GL_TEXTURE_CUBE_MAP, out.levels, GL_RGBA16F, n, n);
    set_filtering(GL_LINEAR_MIPMAP_LINEAR);
  }
  out.scale = scale;
  upload_level0(out.texture.get(), n, staging_.data());
  if (out.levels == 1) {
    check_gl("environment prefilter: upload");
    return;
  }

  if (!source_ || source_size_ != n) {
    source_ = make_texture();
    source_size_ = n;
    glBindTexture(GL_TEXTURE_CUBE_MAP, source_.get());
    glTexStorage2D(GL_TEXTURE_CUBE_MAP, full_chain(n), GL_RGBA16F, n, n);
    set_filtering(GL_LINEAR_MIPMAP_LINEAR);
  }
  upload_level0(source_.get(), n, staging_.data());
  glGenerateMipmap(GL_TEXTURE_CUBE_MAP);  // the box chain the samples read from

  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glUseProgram(program_.get());
  glBindTexture(GL_TEXTURE_CUBE_MAP, source_.get());
  glUniform1i(u_source_, 0);
  glUniform1f(u_source_size_, static_cast<float>(n));
  glUniform1i(u_samples_, config_.samples);
  glBindVertexArray(empty_vao_.get());
  for (int level = 1; level < out.levels; ++level) {
    const int size = std::max(n >> level, 1);
    const float roughness = static_cast<float>(level) / static_cast<float>(out.levels - 1);
    glViewport(0, 0, size, size);
    glUniform1f(u_size_, static_cast<float>(size));
    glUniform1f(u_alpha_, roughness * roughness);
    for (int f = 0; f < 6; ++f) {
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                             static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f),
                             out.texture.get(), level);
      glUniform1i(u_face_, f);
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
  }
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
  glBindVertexArray(0);
  check_gl("environment prefilter");
}

Cubemap read_environment_level(const EnvironmentTexture& texture, int level) {
  if (!texture.texture || level < 0 || level >= texture.levels)
    throw std::invalid_argument("read_environment_level: no such level " + std::to_string(level));
  const int size = std::max(texture.face_size >> level, 1);
  GlFramebuffer fb = make_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fb.get());
  Cubemap out(size);
  std::vector<float> rgba(static_cast<std::size_t>(size) * size * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  for (int f = 0; f < 6; ++f) {
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                           static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f),
                           texture.texture.get(), level);
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
