#pragma once
// RAII for the rendering half of the tethered display: the GBM device on the card's
// descriptor, the GBM surface whose buffers are scanned out, the EGL display on the GBM
// platform (eglGetPlatformDisplay(EGL_PLATFORM_GBM_KHR)), its GLES 2 context and window
// surface, and a locked front buffer with its DRM framebuffer. Each type frees its handle and
// only that; ScanoutSurface (scanout_surface.hpp) owns them in the order they must go.
#include <EGL/egl.h>
#include <gbm.h>

#include <cstdint>
#include <memory>
#include <utility>

#include "core/image.hpp"

namespace probeless::display {

struct GbmDeviceDeleter {
  void operator()(gbm_device* d) const { gbm_device_destroy(d); }
};
struct GbmSurfaceDeleter {
  void operator()(gbm_surface* s) const { gbm_surface_destroy(s); }
};
using GbmDevice = std::unique_ptr<gbm_device, GbmDeviceDeleter>;
using GbmSurface = std::unique_ptr<gbm_surface, GbmSurfaceDeleter>;

// An initialised EGLDisplay; eglTerminate() on destruction. Mesa gives one EGLDisplay per
// gbm_device, and each display owns its gbm_device, so nobody else shares it.
class EglDisplayHandle {
 public:
  EglDisplayHandle() = default;
  explicit EglDisplayHandle(EGLDisplay d) : display_(d) {}
  ~EglDisplayHandle() { reset(); }
  EglDisplayHandle(EglDisplayHandle&& o) noexcept
      : display_(std::exchange(o.display_, EGL_NO_DISPLAY)) {}
  EglDisplayHandle& operator=(EglDisplayHandle&& o) noexcept {
    if (this != &o) {
      reset();
      display_ = std::exchange(o.display_, EGL_NO_DISPLAY);
    }
    return *this;
  }
  EglDisplayHandle(const EglDisplayHandle&) = delete;
  EglDisplayHandle& operator=(const EglDisplayHandle&) = delete;
  EGLDisplay get() const { return display_; }
  void reset();

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
};

// An EGLContext or EGLSurface of a display, destroyed (after being made not current) with it.
class EglContextHandle {
 public:
  EglContextHandle(EGLDisplay d, EGLContext c) : display_(d), context_(c) {}
  ~EglContextHandle();
  EglContextHandle(const EglContextHandle&) = delete;
  EglContextHandle& operator=(const EglContextHandle&) = delete;
  EGLContext get() const { return context_; }

 private:
  EGLDisplay display_;
  EGLContext context_;
};

class EglSurfaceHandle {
 public:
  EglSurfaceHandle(EGLDisplay d, EGLSurface s) : display_(d), surface_(s) {}
  ~EglSurfaceHandle();
  EglSurfaceHandle(const EglSurfaceHandle&) = delete;
  EglSurfaceHandle& operator=(const EglSurfaceHandle&) = delete;
  EGLSurface get() const { return surface_; }

 private:
  EGLDisplay display_;
  EGLSurface surface_;
};

// The buffer eglSwapBuffers() just finished, locked out of the GBM surface's rotation until
// this is destroyed (gbm_surface_release_buffer), with the DRM framebuffer that scans it out.
// The framebuffer is made once per buffer and kept as the buffer's user data (drmModeRmFB
// when GBM destroys the buffer), so steady-state flips add no framebuffers.
class FrontBuffer {
 public:
  FrontBuffer(gbm_surface* surface, int drm_fd);  // locks; throws DisplayError
  ~FrontBuffer();
  FrontBuffer(const FrontBuffer&) = delete;
  FrontBuffer& operator=(const FrontBuffer&) = delete;

  std::uint32_t framebuffer() const { return fb_; }
  // The buffer's pixels as scanned out (gbm_bo_map, XRGB8888 -> RGB): what the screen shows.
  ImageRGB8 read() const;

 private:
  gbm_surface* surface_;
  gbm_bo* bo_;
  std::uint32_t fb_ = 0;
};

}  // namespace probeless::display
