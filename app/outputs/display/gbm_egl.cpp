#include "app/outputs/display/gbm_egl.hpp"

#include <fmt/format.h>
#include <xf86drmMode.h>

#include <cerrno>
#include <cstring>

#include "app/outputs/display/display_mode.hpp"

namespace probeless::display {
namespace {

struct FramebufferTag {
  int drm_fd;
  std::uint32_t fb;
};

void remove_framebuffer(gbm_bo*, void* data) {
  auto* tag = static_cast<FramebufferTag*>(data);
  drmModeRmFB(tag->drm_fd, tag->fb);
  delete tag;
}

}  // namespace

void EglDisplayHandle::reset() {
  if (display_ != EGL_NO_DISPLAY) eglTerminate(display_);
  display_ = EGL_NO_DISPLAY;
}

EglContextHandle::~EglContextHandle() {
  if (context_ == EGL_NO_CONTEXT) return;
  if (eglGetCurrentContext() == context_)
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
}

EglSurfaceHandle::~EglSurfaceHandle() {
  if (surface_ == EGL_NO_SURFACE) return;
  if (eglGetCurrentSurface(EGL_DRAW) == surface_)
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroySurface(display_, surface_);
}

FrontBuffer::FrontBuffer(gbm_surface* surface, int drm_fd)
    : surface_(surface), bo_(gbm_surface_lock_front_buffer(surface)) {
  if (bo_ == nullptr) throw DisplayError("gbm_surface_lock_front_buffer: no buffer after swap");
  if (auto* tag = static_cast<FramebufferTag*>(gbm_bo_get_user_data(bo_))) {
    fb_ = tag->fb;
    return;
  }
  const std::uint32_t handles[4] = {gbm_bo_get_handle(bo_).u32, 0, 0, 0};
  const std::uint32_t pitches[4] = {gbm_bo_get_stride(bo_), 0, 0, 0};
  const std::uint32_t offsets[4] = {0, 0, 0, 0};
  if (drmModeAddFB2(drm_fd, gbm_bo_get_width(bo_), gbm_bo_get_height(bo_), gbm_bo_get_format(bo_),
                    handles, pitches, offsets, &fb_, 0) != 0) {
    const int err = errno;
    gbm_surface_release_buffer(surface_, bo_);
    throw DisplayError(fmt::format("drmModeAddFB2 ({}x{}): {}", gbm_bo_get_width(bo_),
                                   gbm_bo_get_height(bo_), std::strerror(err)));
  }
  gbm_bo_set_user_data(bo_, new FramebufferTag{drm_fd, fb_}, remove_framebuffer);
}

FrontBuffer::~FrontBuffer() {
  gbm_surface_release_buffer(surface_, bo_);
}

ImageRGB8 FrontBuffer::read() const {
  const std::uint32_t w = gbm_bo_get_width(bo_), h = gbm_bo_get_height(bo_);
  std::uint32_t stride = 0;
  void* map_data = nullptr;
  const void* map = gbm_bo_map(bo_, 0, 0, w, h, GBM_BO_TRANSFER_READ, &stride, &map_data);
  if (map == nullptr)
    throw DisplayError(fmt::format("gbm_bo_map of the front buffer: {}", std::strerror(errno)));
  ImageRGB8 out(static_cast<int>(w), static_cast<int>(h));
  for (std::uint32_t y = 0; y < h; ++y) {
    // XRGB8888 is a little-endian 32-bit word: bytes B, G, R, X.
    const auto* src = static_cast<const std::uint8_t*>(map) + static_cast<std::size_t>(y) * stride;
    std::uint8_t* dst = out.row(static_cast<int>(y));
    for (std::uint32_t x = 0; x < w; ++x) {
      dst[3 * x + 0] = src[4 * x + 2];
      dst[3 * x + 1] = src[4 * x + 1];
      dst[3 * x + 2] = src[4 * x + 0];
    }
  }
  gbm_bo_unmap(bo_, map_data);
  return out;
}

}  // namespace probeless::display
