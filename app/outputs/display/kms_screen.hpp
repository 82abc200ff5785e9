#pragma once
// One open tethered screen: the KMS mode set (kms_modeset.hpp) and the GBM/EGL surface
// (scanout_surface.hpp) together. present() draws a frame, swaps, and shows it: the first
// frame with drmModeSetCrtc, every later one with a page flip whose vblank event it waits
// for. Synchronous and single-threaded; KmsDisplay (kms_display.hpp) runs it on its own thread.
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "app/outputs/display/kms_modeset.hpp"
#include "app/outputs/display/kms_screen_config.hpp"
#include "app/outputs/display/scanout_surface.hpp"

namespace probeless::display {

struct PresentResult {
  bool mode_set = false;          // the first frame: drmModeSetCrtc, no flip event
  std::optional<FlipEvent> flip;  // every later frame
  double draw_ms = 0;             // upload and draw calls (work may still be queued)
  double swap_ms = 0;             // eglSwapBuffers: the rendering finished into a buffer
  double show_ms = 0;             // mode set, or flip until its vblank event
};

class KmsScreen {
 public:
  // Opens and chooses everything; nothing is shown until the first present(). Throws
  // DisplayError (bad mode string, no card, connector, mode, busy device, EGL on GBM).
  explicit KmsScreen(const KmsScreenConfig& config);
  // Puts the console (or whatever the CRTC showed) back before freeing our buffers.
  ~KmsScreen();
  KmsScreen(const KmsScreen&) = delete;
  KmsScreen& operator=(const KmsScreen&) = delete;

  PresentResult present(const ImageRGB8& image);
  // What the CRTC scans out now, read from the front buffer (for tests and diagnostics).
  ImageRGB8 read_scanout() const;

  const KmsTarget& target() const { return modeset_.target(); }
  const std::string& renderer() const { return surface_.renderer(); }
  const Viewport& last_viewport() const { return surface_.last_viewport(); }

 private:
  std::chrono::milliseconds flip_timeout_;
  KmsModeset modeset_;
  ScanoutSurface surface_;
  std::unique_ptr<FrontBuffer> front_;  // on screen; released once the next one is
};

}  // namespace probeless::display
