#pragma once
// The KMS half of the tethered display: one card, one connector, the CRTC that drives it and
// the mode to set, chosen from config (docs/display.md). Legacy modesetting: drmModeSetCrtc
// for the first frame, then drmModePageFlip with an event per frame, waited for with a
// bounded poll. The CRTC as it was before (the console's framebuffer) comes back on
// restore() and on destruction.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "app/outputs/display/drm_handles.hpp"
#include "core/time.hpp"

namespace probeless::display {

struct KmsTarget {
  std::filesystem::path card;
  std::string driver;     // the kernel driver, "virtio_gpu"
  std::string connector;  // "Virtual-1"
  ModeInfo mode;
};

// A completed page flip: the frame became visible at the vblank `sequence`, at `timestamp_ns`
// on CLOCK_MONOTONIC (the kernel's vblank timestamp, the clock core/time.hpp uses).
struct FlipEvent {
  std::uint64_t sequence = 0;
  TimestampNs timestamp_ns = 0;
};

class KmsModeset {
 public:
  // `card` empty: the first /dev/dri/card* with a usable connector. `connector` empty: the
  // first connected one. No mode: the preferred one. Throws DisplayError saying which of
  // these failed, and when another process is the card's DRM master (device busy).
  KmsModeset(const std::string& card, const std::string& connector,
             const std::optional<ModeRequest>& mode,
             const std::filesystem::path& dri_dir = "/dev/dri");
  ~KmsModeset();
  KmsModeset(const KmsModeset&) = delete;
  KmsModeset& operator=(const KmsModeset&) = delete;

  int fd() const { return fd_.get(); }
  const KmsTarget& target() const { return target_; }
  int width() const { return mode_.hdisplay; }
  int height() const { return mode_.vdisplay; }
  bool mode_set() const { return saved_ != nullptr; }

  // Scans out `fb` in the chosen mode (the first frame), saving the CRTC's previous state.
  void set_crtc(std::uint32_t fb);
  // Queues a flip to `fb` at the next vblank and waits up to `timeout` for its event.
  FlipEvent page_flip(std::uint32_t fb, std::chrono::milliseconds timeout);
  // Puts back the framebuffer and mode the CRTC had before set_crtc(); idempotent.
  void restore();

 private:
  void open(const std::filesystem::path& path, const std::string& connector,
            const std::optional<ModeRequest>& mode);

  UniqueFd fd_;
  KmsTarget target_;
  std::uint32_t connector_id_ = 0;
  std::uint32_t crtc_id_ = 0;
  drmModeModeInfo mode_{};
  ModeCrtc saved_;  // the CRTC before our first set_crtc(); null until then and after restore
};

}  // namespace probeless::display
