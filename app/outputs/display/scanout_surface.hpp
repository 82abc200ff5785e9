#pragma once
// Where the tethered display draws: a GBM surface of the mode's size on the card, an EGL
// window surface on it (EGL_PLATFORM_GBM_KHR, GLES 2), and the one draw it does: the
// composite as a texture on a quad, letterboxed into the screen. Not thread-safe: the EGL
// context is current on the thread that made the surface and must stay there.
#include <GLES2/gl2.h>

#include <memory>
#include <optional>
#include <string>

#include "app/outputs/display/display_mode.hpp"
#include "app/outputs/display/gbm_egl.hpp"
#include "core/image.hpp"

namespace probeless::display {

class ScanoutSurface {
 public:
  // Throws DisplayError naming the step that failed (GBM, EGL platform, config, context).
  ScanoutSurface(int drm_fd, int width, int height);
  ~ScanoutSurface();
  ScanoutSurface(const ScanoutSurface&) = delete;
  ScanoutSurface& operator=(const ScanoutSurface&) = delete;

  // Clears the screen to black and draws `image` scaled into letterbox(), bilinear.
  void draw(const ImageRGB8& image);
  // Finishes the frame (eglSwapBuffers) and locks the buffer that now holds it.
  std::unique_ptr<FrontBuffer> swap();

  const std::string& renderer() const { return renderer_; }  // GL_RENDERER, "llvmpipe (...)"
  const Viewport& last_viewport() const { return viewport_; }

 private:
  int drm_fd_;
  int width_, height_;
  GbmDevice gbm_;
  GbmSurface gbm_surface_;
  EglDisplayHandle display_;
  std::optional<EglContextHandle> context_;
  std::optional<EglSurfaceHandle> surface_;
  GLuint program_ = 0, texture_ = 0, quad_ = 0;
  int texture_width_ = 0, texture_height_ = 0;
  Viewport viewport_;
  std::string renderer_;
};

}  // namespace probeless::display
