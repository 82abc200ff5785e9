#pragma once
// RAII for the libdrm handles of the tethered display: the card's descriptor and the mode
// objects libdrm allocates (resources, connector, encoder, CRTC), plus the few queries the
// display and `probeless devices` share. Copying is disabled; every handle frees itself. The
// card's descriptor is a base/unique_fd.hpp UniqueFd.
#include <xf86drm.h>
#include <xf86drmMode.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/outputs/display/display_mode.hpp"
#include "base/unique_fd.hpp"

namespace probeless::display {

struct ResourcesDeleter {
  void operator()(drmModeRes* p) const { drmModeFreeResources(p); }
};
struct ConnectorDeleter {
  void operator()(drmModeConnector* p) const { drmModeFreeConnector(p); }
};
struct EncoderDeleter {
  void operator()(drmModeEncoder* p) const { drmModeFreeEncoder(p); }
};
struct CrtcDeleter {
  void operator()(drmModeCrtc* p) const { drmModeFreeCrtc(p); }
};
using ModeResources = std::unique_ptr<drmModeRes, ResourcesDeleter>;
using ModeConnector = std::unique_ptr<drmModeConnector, ConnectorDeleter>;
using ModeEncoder = std::unique_ptr<drmModeEncoder, EncoderDeleter>;
using ModeCrtc = std::unique_ptr<drmModeCrtc, CrtcDeleter>;

// /dev/dri/card* in numeric order (card10 after card9), the primary nodes that do KMS;
// renderD* nodes cannot. Empty when the directory is missing.
std::vector<std::filesystem::path> list_cards(const std::filesystem::path& dri_dir);

// Opens a card read-write; DisplayError saying why not (missing, permissions, not DRM).
UniqueFd open_card(const std::filesystem::path& path);

// The card's mode resources; DisplayError when it is not a KMS device (a render-only GPU).
ModeResources get_resources(const UniqueFd& fd, const std::filesystem::path& path);

// "HDMI-A-1", "Virtual-1", "eDP-1": as the kernel (and Xorg/Weston/sysfs) name connectors.
std::string connector_name(const drmModeConnector& c);
ModeInfo mode_info(const drmModeModeInfo& m);
std::string driver_name(const UniqueFd& fd);  // "virtio_gpu", "vc4", "rockchip", ...

}  // namespace probeless::display
