#include "app/outputs/display/kms_screen.hpp"

#include <spdlog/spdlog.h>

namespace probeless::display {
namespace {

std::optional<ModeRequest> mode_request(const std::string& text) {
  if (text.empty()) return std::nullopt;
  return parse_mode_request(text);
}

}  // namespace

KmsScreen::KmsScreen(const KmsScreenConfig& config)
    : flip_timeout_(config.flip_timeout),
      modeset_(config.card, config.connector, mode_request(config.mode), config.dri_dir),
      surface_(modeset_.fd(), modeset_.width(), modeset_.height()) {
  spdlog::info("display: {} ({}) connector {} mode {}, drawing with {}", target().card.string(),
               target().driver, target().connector, to_string(target().mode), surface_.renderer());
}

KmsScreen::~KmsScreen() {
  modeset_.restore();
}

PresentResult KmsScreen::present(const ImageRGB8& image) {
  PresentResult result;
  const auto t0 = monotonic_now_ns();
  surface_.draw(image);
  const auto t1 = monotonic_now_ns();
  auto next = surface_.swap();
  const auto t2 = monotonic_now_ns();
  if (!modeset_.mode_set()) {
    modeset_.set_crtc(next->framebuffer());
    result.mode_set = true;
  } else {
    result.flip = modeset_.page_flip(next->framebuffer(), flip_timeout_);
  }
  const auto t3 = monotonic_now_ns();
  result.draw_ms = static_cast<double>(t1 - t0) * 1e-6;
  result.swap_ms = static_cast<double>(t2 - t1) * 1e-6;
  result.show_ms = static_cast<double>(t3 - t2) * 1e-6;
  // The old buffer left the screen with the flip: GBM may now draw into it again.
  front_ = std::move(next);
  return result;
}

ImageRGB8 KmsScreen::read_scanout() const {
  if (!front_) throw DisplayError("nothing presented yet");
  return front_->read();
}

}  // namespace probeless::display
