#include "app/render/gl_objects.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

namespace probeless::render {
namespace {

template <typename Name, auto Gen>
Name generate() {
  GLuint n = 0;
  Gen(1, &n);
  if (n == 0) throw GlError("glGen* returned no name (is a GL context current?)");
  return Name(n);
}

void gen_buffers(GLsizei n, GLuint* p) {
  glGenBuffers(n, p);
}
void gen_textures(GLsizei n, GLuint* p) {
  glGenTextures(n, p);
}
void gen_framebuffers(GLsizei n, GLuint* p) {
  glGenFramebuffers(n, p);
}
void gen_renderbuffers(GLsizei n, GLuint* p) {
  glGenRenderbuffers(n, p);
}
void gen_vertex_arrays(GLsizei n, GLuint* p) {
  glGenVertexArrays(n, p);
}

// A shader object lives only until the program is linked.
struct Shader {
  GLuint name;
  ~Shader() { glDeleteShader(name); }
};

GLuint compile(std::string_view program_name, GLenum kind, std::string_view source) {
  GLuint shader = glCreateShader(kind);
  if (shader == 0) throw GlError("glCreateShader failed (is a GL context current?)");
  const char* text = source.data();
  const auto length = static_cast<GLint>(source.size());
  glShaderSource(shader, 1, &text, &length);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint log_length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &log_length);
    std::vector<char> log(static_cast<std::size_t>(std::max(log_length, 1)), '\0');
    glGetShaderInfoLog(shader, log_length, nullptr, log.data());
    glDeleteShader(shader);
    throw GlError(fmt::format("{} {} shader does not compile:\n{}", program_name,
                              kind == GL_VERTEX_SHADER ? "vertex" : "fragment", log.data()));
  }
  return shader;
}

}  // namespace

const char* gl_error_name(GLenum code) {
  switch (code) {
    case GL_NO_ERROR:
      return "GL_NO_ERROR";
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    default:
      return "unknown GL error";
  }
}

void check_gl(const char* what) {
  GLenum code = glGetError();
  if (code == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  throw GlError(fmt::format("{}: {} (0x{:04x})", what, gl_error_name(code), code));
}

GlBuffer make_buffer() {
  return generate<GlBuffer, gen_buffers>();
}
GlTexture make_texture() {
  return generate<GlTexture, gen_textures>();
}
GlFramebuffer make_framebuffer() {
  return generate<GlFramebuffer, gen_framebuffers>();
}
GlRenderbuffer make_renderbuffer() {
  return generate<GlRenderbuffer, gen_renderbuffers>();
}
GlVertexArray make_vertex_array() {
  return generate<GlVertexArray, gen_vertex_arrays>();
}

GlProgram link_program(std::string_view name, std::string_view vertex_source,
                       std::string_view fragment_source) {
  Shader vs{compile(name, GL_VERTEX_SHADER, vertex_source)};
  Shader fs{compile(name, GL_FRAGMENT_SHADER, fragment_source)};
  GlProgram program(glCreateProgram());
  if (!program) throw GlError("glCreateProgram failed");
  glAttachShader(program.get(), vs.name);
  glAttachShader(program.get(), fs.name);
  glLinkProgram(program.get());
  GLint ok = GL_FALSE;
  glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint log_length = 0;
    glGetProgramiv(program.get(), GL_INFO_LOG_LENGTH, &log_length);
    std::vector<char> log(static_cast<std::size_t>(std::max(log_length, 1)), '\0');
    glGetProgramInfoLog(program.get(), log_length, nullptr, log.data());
    throw GlError(fmt::format("{} program does not link:\n{}", name, log.data()));
  }
  return program;
}

}  // namespace probeless::render
