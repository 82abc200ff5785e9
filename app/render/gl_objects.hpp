#pragma once
// RAII for OpenGL ES object names, and the few helpers every GL user here needs. Objects
// must be destroyed while their context is current (the renderer owns them and the context
// outlives them).
#include <GLES3/gl3.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace probeless::render {

class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

const char* gl_error_name(GLenum code);
// Throws GlError naming `what` and the first pending glGetError() code, if any.
void check_gl(const char* what);

// One GL name of one kind; Deleter is a function deleting n names (glDeleteBuffers, ...).
template <void (*Delete)(GLsizei, const GLuint*)>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GLuint name) : name_(name) {}
  ~GlName() { reset(); }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;
  GlName(GlName&& o) noexcept : name_(std::exchange(o.name_, 0)) {}
  GlName& operator=(GlName&& o) noexcept {
    if (this != &o) {
      reset();
      name_ = std::exchange(o.name_, 0);
    }
    return *this;
  }
  GLuint get() const { return name_; }
  explicit operator bool() const { return name_ != 0; }
  void reset() {
    if (name_ != 0) Delete(1, &name_);
    name_ = 0;
  }

 private:
  GLuint name_ = 0;
};

namespace detail {
inline void delete_buffers(GLsizei n, const GLuint* p) {
  glDeleteBuffers(n, p);
}
inline void delete_textures(GLsizei n, const GLuint* p) {
  glDeleteTextures(n, p);
}
inline void delete_framebuffers(GLsizei n, const GLuint* p) {
  glDeleteFramebuffers(n, p);
}
inline void delete_renderbuffers(GLsizei n, const GLuint* p) {
  glDeleteRenderbuffers(n, p);
}
inline void delete_vertex_arrays(GLsizei n, const GLuint* p) {
  glDeleteVertexArrays(n, p);
}
inline void delete_program(GLsizei, const GLuint* p) {
  glDeleteProgram(*p);
}
}  // namespace detail

using GlBuffer = GlName<detail::delete_buffers>;
using GlTexture = GlName<detail::delete_textures>;
using GlFramebuffer = GlName<detail::delete_framebuffers>;
using GlRenderbuffer = GlName<detail::delete_renderbuffers>;
using GlVertexArray = GlName<detail::delete_vertex_arrays>;
using GlProgram = GlName<detail::delete_program>;

GlBuffer make_buffer();
GlTexture make_texture();
GlFramebuffer make_framebuffer();
GlRenderbuffer make_renderbuffer();
GlVertexArray make_vertex_array();

// Compiles and links a program; throws GlError with the info log, prefixed by `name`.
GlProgram link_program(std::string_view name, std::string_view vertex_source,
                       std::string_view fragment_source);

}  // namespace probeless::render
