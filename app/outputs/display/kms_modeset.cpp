#include "app/outputs/display/kms_modeset.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <spdlog/spdlog.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace probeless::display {
namespace {

std::string busy_message(const std::filesystem::path& card) {
  return fmt::format(
      "{} is busy: another process is its DRM master (a display server, or "
      "another probeless); stop it or use another card",
      card.string());
}

// The CRTC for a connector: the one its encoder already drives (no modeset flicker), else
// the first its encoders can drive.
std::uint32_t find_crtc(int fd, const drmModeRes& res, const drmModeConnector& conn) {
  if (conn.encoder_id != 0) {
    ModeEncoder enc(drmModeGetEncoder(fd, conn.encoder_id));
    if (enc && enc->crtc_id != 0) return enc->crtc_id;
  }
  for (int e = 0; e < conn.count_encoders; ++e) {
    ModeEncoder enc(drmModeGetEncoder(fd, conn.encoders[e]));
    if (!enc) continue;
    for (int c = 0; c < res.count_crtcs; ++c)
      if (enc->possible_crtcs & (1u << c)) return res.crtcs[c];
  }
  return 0;
}

struct FlipWait {
  bool done = false;
  FlipEvent event;
};

void on_page_flip(int, unsigned sequence, unsigned tv_sec, unsigned tv_usec, void* data) {
  auto* wait = static_cast<FlipWait*>(data);
  wait->done = true;
  wait->event.sequence = sequence;
  wait->event.timestamp_ns =
      static_cast<TimestampNs>(tv_sec) * 1'000'000'000LL + static_cast<TimestampNs>(tv_usec) * 1000;
}

}  // namespace

KmsModeset::KmsModeset(const std::string& card, const std::string& connector,
                       const std::optional<ModeRequest>& mode,
                       const std::filesystem::path& dri_dir) {
  if (!card.empty()) {
    open(card_path(card, dri_dir), connector, mode);
    return;
  }
  const auto cards = list_cards(dri_dir);
  if (cards.empty())
    throw DisplayError(
        fmt::format("no {}/card*: no KMS display driver is loaded (a board's "
                    "vc4/rockchip/i915, or virtio-gpu in a VM)",
                    dri_dir.string()));
  // Several cards (a render-only GPU beside the display controller): the first that has the
  // connector wins; when none has, every card's reason is reported.
  std::string reasons;
  for (const auto& path : cards) {
    try {
      open(path, connector, mode);
      return;
    } catch (const DisplayError& e) {
      reasons += (reasons.empty() ? "" : "; ") + std::string(e.what());
      fd_.reset();
    }
  }
  throw DisplayError(reasons);
}

void KmsModeset::open(const std::filesystem::path& path, const std::string& connector_name_wanted,
                      const std::optional<ModeRequest>& mode_wanted) {
  fd_ = open_card(path);
  const ModeResources res = get_resources(fd_, path);
  const std::string card = path.filename().string();

  std::vector<ModeConnector> connectors;
  std::vector<ConnectorInfo> infos;
  for (int i = 0; i < res->count_connectors; ++i) {
    ModeConnector c(drmModeGetConnector(fd_.get(), res->connectors[i]));
    if (!c) continue;
    infos.push_back({connector_name(*c), c->connection == DRM_MODE_CONNECTED});
    connectors.push_back(std::move(c));
  }
  const std::size_t ci = choose_connector(infos, connector_name_wanted, card);
  const drmModeConnector& conn = *connectors[ci];

  std::vector<ModeInfo> modes;
  for (int m = 0; m < conn.count_modes; ++m) modes.push_back(mode_info(conn.modes[m]));
  const std::size_t mi = choose_mode(modes, mode_wanted, infos[ci].name);

  crtc_id_ = find_crtc(fd_.get(), *res, conn);
  if (crtc_id_ == 0)
    throw DisplayError(fmt::format("no CRTC can drive {} on {}", infos[ci].name, card));
  // The first opener of a card becomes its master; if we did not, someone else is. Checked
  // here so that a busy card is reported at open, not as a failed mode set.
  if (!drmIsMaster(fd_.get()) && drmSetMaster(fd_.get()) != 0)
    throw DisplayError(busy_message(path));

  connector_id_ = conn.connector_id;
  mode_ = conn.modes[mi];
  target_ = {path, driver_name(fd_), infos[ci].name, modes[mi]};
}

KmsModeset::~KmsModeset() {
  restore();
}

void KmsModeset::set_crtc(std::uint32_t fb) {
  if (!saved_) saved_.reset(drmModeGetCrtc(fd_.get(), crtc_id_));
  std::uint32_t connector = connector_id_;
  if (drmModeSetCrtc(fd_.get(), crtc_id_, fb, 0, 0, &connector, 1, &mode_) != 0) {
    const int err = errno;
    if (err == EACCES || err == EPERM) throw DisplayError(busy_message(target_.card));
    throw DisplayError(fmt::format("drmModeSetCrtc({} {} on {}): {}", target_.connector,
                                   to_string(target_.mode), target_.card.filename().string(),
                                   std::strerror(err)));
  }
}

FlipEvent KmsModeset::page_flip(std::uint32_t fb, std::chrono::milliseconds timeout) {
  FlipWait wait;
  if (drmModePageFlip(fd_.get(), crtc_id_, fb, DRM_MODE_PAGE_FLIP_EVENT, &wait) != 0) {
    const int err = errno;
    if (err == EACCES || err == EPERM) throw DisplayError(busy_message(target_.card));
    throw DisplayError(fmt::format("drmModePageFlip on {}: {}", target_.card.filename().string(),
                                   std::strerror(err)));
  }
  drmEventContext events{};
  events.version = 2;
  events.page_flip_handler = on_page_flip;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!wait.done) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0)
      throw DisplayError(fmt::format("no page-flip event from {} within {} ms (vblank stuck)",
                                     target_.card.filename().string(), timeout.count()));
    pollfd p{fd_.get(), POLLIN, 0};
    const int n = ::poll(&p, 1, static_cast<int>(left.count()));
    if (n < 0 && errno != EINTR)
      throw DisplayError(
          fmt::format("poll on {}: {}", target_.card.string(), std::strerror(errno)));
    if (n > 0 && drmHandleEvent(fd_.get(), &events) != 0)
      throw DisplayError(fmt::format("drmHandleEvent on {} failed", target_.card.string()));
  }
  return wait.event;
}

void KmsModeset::restore() {
  if (!saved_ || !fd_) return;
  const ModeCrtc saved = std::move(saved_);
  std::uint32_t connector = connector_id_;
  // A CRTC that was off (no console) is switched off again rather than left on our buffer,
  // which is about to be freed.
  const int rc = saved->mode_valid
                     ? drmModeSetCrtc(fd_.get(), saved->crtc_id, saved->buffer_id, saved->x,
                                      saved->y, &connector, 1, &saved->mode)
                     : drmModeSetCrtc(fd_.get(), saved->crtc_id, 0, 0, 0, nullptr, 0, nullptr);
  if (rc != 0)
    spdlog::warn("display: restoring the CRTC of {} failed: {}", target_.connector,
                 std::strerror(errno));
}

}  // namespace probeless::display
