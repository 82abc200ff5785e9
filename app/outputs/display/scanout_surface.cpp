#include "app/outputs/display/scanout_surface.hpp"

#include <EGL/eglext.h>
#include <fmt/format.h>

#include <vector>

namespace probeless::display {
namespace {

std::string egl_failure(const char* call) {
  return fmt::format("{} failed (EGL error 0x{:04x})", call, eglGetError());
}

// Clip-space quad as a triangle strip; the texture's row 0 is the image's top row, so v runs
// downwards while y runs upwards.
constexpr float kQuad[] = {-1, -1, 0, 1, 1, -1, 1, 1, -1, 1, 0, 0, 1, 1, 1, 0};

constexpr const char* kVertexShader = R"(#version 100
attribute vec2 position;
attribute vec2 texcoord;
varying vec2 uv;
void main() {
  uv = texcoord;
  gl_Position = vec4(position, 0.0, 1.0);
})";

constexpr const char* kFragmentShader = R"(#version 100
precision mediump float;
uniform sampler2D image;
varying vec2 uv;
void main() { gl_FragColor = vec4(texture2D(image, uv).rgb, 1.0); })";

GLuint compile(GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[512] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw DisplayError(fmt::format("display shader: {}", log));
  }
  return shader;
}

// An RGB config whose native visual is XRGB8888, the format the GBM surface is made in:
// Mesa lists ARGB and XRGB configs alike, and a mismatch fails at surface creation.
EGLConfig choose_config(EGLDisplay display) {
  const EGLint attribs[] = {EGL_SURFACE_TYPE,
                            EGL_WINDOW_BIT,
                            EGL_RED_SIZE,
                            8,
                            EGL_GREEN_SIZE,
                            8,
                            EGL_BLUE_SIZE,
                            8,
                            EGL_ALPHA_SIZE,
                            0,
                            EGL_RENDERABLE_TYPE,
                            EGL_OPENGL_ES2_BIT,
                            EGL_NONE};
  EGLint count = 0;
  if (!eglChooseConfig(display, attribs, nullptr, 0, &count) || count == 0)
    throw DisplayError(egl_failure("eglChooseConfig (RGB888 window, GLES 2)"));
  std::vector<EGLConfig> configs(static_cast<std::size_t>(count));
  eglChooseConfig(display, attribs, configs.data(), count, &count);
  for (EGLint i = 0; i < count; ++i) {
    EGLint visual = 0;
    if (eglGetConfigAttrib(display, configs[i], EGL_NATIVE_VISUAL_ID, &visual) &&
        static_cast<std::uint32_t>(visual) == GBM_FORMAT_XRGB8888)
      return configs[i];
  }
  throw DisplayError("no EGL config renders into an XRGB8888 GBM surface");
}

}  // namespace

ScanoutSurface::ScanoutSurface(int drm_fd, int width, int height)
    : drm_fd_(drm_fd), width_(width), height_(height) {
  gbm_.reset(gbm_create_device(drm_fd));
  if (!gbm_) throw DisplayError("gbm_create_device failed (no GBM backend for this card)");
  gbm_surface_.reset(gbm_surface_create(gbm_.get(), static_cast<std::uint32_t>(width),
                                        static_cast<std::uint32_t>(height), GBM_FORMAT_XRGB8888,
                                        GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING));
  if (!gbm_surface_)
    throw DisplayError(fmt::format("gbm_surface_create {}x{} XRGB8888 failed", width, height));

  EGLDisplay display = eglGetPlatformDisplay(EGL_PLATFORM_GBM_KHR, gbm_.get(), nullptr);
  if (display == EGL_NO_DISPLAY) throw DisplayError(egl_failure("eglGetPlatformDisplay(GBM)"));
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor))
    throw DisplayError(egl_failure("eglInitialize(GBM)"));
  display_ = EglDisplayHandle(display);
  if (!eglBindAPI(EGL_OPENGL_ES_API)) throw DisplayError(egl_failure("eglBindAPI"));
  const EGLConfig config = choose_config(display);
  const EGLint context_attribs[] = {EGL_CONTEXT_CLIENT_VERSION, 2, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
  if (context == EGL_NO_CONTEXT) throw DisplayError(egl_failure("eglCreateContext(GLES 2)"));
  context_.emplace(display, context);
  EGLSurface surface = eglCreatePlatformWindowSurface(display, config, gbm_surface_.get(), nullptr);
  if (surface == EGL_NO_SURFACE)
    throw DisplayError(egl_failure("eglCreatePlatformWindowSurface(gbm_surface)"));
  surface_.emplace(display, surface);
  if (!eglMakeCurrent(display, surface, surface, context))
    throw DisplayError(egl_failure("eglMakeCurrent"));
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  renderer_ = r != nullptr ? r : "?";

  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glBindAttribLocation(program_, 0, "position");
  glBindAttribLocation(program_, 1, "texcoord");
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint linked = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &linked);
  if (!linked) throw DisplayError("display shader program failed to link");
  glGenBuffers(1, &quad_);
  glBindBuffer(GL_ARRAY_BUFFER, quad_);
  glBufferData(GL_ARRAY_BUFFER, sizeof kQuad, kQuad, GL_STATIC_DRAW);
  glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // RGB rows of any width are tightly packed
}

ScanoutSurface::~ScanoutSurface() {
  if (context_ && eglGetCurrentContext() == context_->get()) {
    glDeleteTextures(1, &texture_);
    glDeleteBuffers(1, &quad_);
    glDeleteProgram(program_);
  }
  // The members go in reverse order: surface, context, display (eglTerminate), then the
  // GBM surface and device that EGL was using.
}

void ScanoutSurface::draw(const ImageRGB8& image) {
  glBindTexture(GL_TEXTURE_2D, texture_);
  if (image.width() != texture_width_ || image.height() != texture_height_) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, image.width(), image.height(), 0, GL_RGB,
                 GL_UNSIGNED_BYTE, image.data());
    texture_width_ = image.width();
    texture_height_ = image.height();
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, image.width(), image.height(), GL_RGB, GL_UNSIGNED_BYTE,
                    image.data());
  }
  glViewport(0, 0, width_, height_);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  viewport_ = letterbox(image.width(), image.height(), width_, height_);
  // GL's window origin is the bottom-left; the bars are symmetric, so only y is mirrored.
  glViewport(viewport_.x, height_ - viewport_.y - viewport_.height, viewport_.width,
             viewport_.height);
  glUseProgram(program_);
  glBindBuffer(GL_ARRAY_BUFFER, quad_);
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float),
                        reinterpret_cast<const void*>(2 * sizeof(float)));
  glUniform1i(glGetUniformLocation(program_, "image"), 0);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  const GLenum err = glGetError();
  if (err != GL_NO_ERROR) throw DisplayError(fmt::format("display draw: GL error 0x{:04x}", err));
}

std::unique_ptr<FrontBuffer> ScanoutSurface::swap() {
  if (!eglSwapBuffers(display_.get(), surface_->get()))
    throw DisplayError(egl_failure("eglSwapBuffers"));
  return std::make_unique<FrontBuffer>(gbm_surface_.get(), drm_fd_);
}

}  // namespace probeless::display
