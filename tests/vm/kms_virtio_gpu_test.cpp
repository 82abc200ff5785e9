// The tethered display against a real KMS driver, virtio-gpu (issue #7 "Tests on real kernel
// drivers"): mode set, page flips with their vblank events, what the CRTC scans out, the
// console's CRTC put back, and the errors a wrong config or a busy card give. Runs inside
// the VM of tests/vm/run_in_vm.sh (check_kms.sh boots it with -device virtio-gpu-pci); on a
// machine without a KMS card it skips, unless PROBELESS_REQUIRE_KMS=1 (set in the VM) makes
// that a failure.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "app/outputs/display/drm_inventory.hpp"
#include "app/outputs/display/kms_screen.hpp"
#include "app/outputs/kms_display.hpp"

namespace probeless::display {
namespace {

using namespace std::chrono_literals;

class VirtioGpu : public ::testing::Test {
 protected:
  void SetUp() override {
    if (list_cards("/dev/dri").empty()) {
      const char* require = std::getenv("PROBELESS_REQUIRE_KMS");
      if (require != nullptr && std::string(require) == "1") FAIL() << "no /dev/dri/card*";
      GTEST_SKIP() << "no /dev/dri/card* (tests/vm/check_kms.sh runs this in a VM)";
    }
  }
};

// llvmpipe under TCG draws a 1280x800 screen (virtio-gpu's preferred mode) in about a second
// and 640x480 in about a third of that: the flipping tests use the small mode.
KmsScreenConfig small_mode() {
  KmsScreenConfig c;
  c.mode = "640x480";
  // virtio-gpu sends the flip event once the host has the update: 1-50 ms measured here, but
  // a CI host under load may stall the VM for longer than a real vblank could take.
  c.flip_timeout = 3s;
  return c;
}

// A 16:9 test card: the left half red, the right half blue, and the frame number in green, so
// a read-back says both where the picture went and which frame it is.
ImageRGB8 test_card(int index, int width = 320, int height = 180) {
  ImageRGB8 img(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      img.at(x, y, 0) = x < width / 2 ? 230 : 0;
      img.at(x, y, 1) = static_cast<std::uint8_t>(index * 7 % 256);
      img.at(x, y, 2) = x < width / 2 ? 0 : 230;
    }
  return img;
}

void expect_pixel(const ImageRGB8& img, int x, int y, int r, int g, int b, const char* what) {
  SCOPED_TRACE(what);
  ASSERT_TRUE(img.contains(x, y)) << x << "," << y;
  EXPECT_NEAR(img.at(x, y, 0), r, 2) << "at " << x << "," << y;
  EXPECT_NEAR(img.at(x, y, 1), g, 2) << "at " << x << "," << y;
  EXPECT_NEAR(img.at(x, y, 2), b, 2) << "at " << x << "," << y;
}

// The CRTC's state seen from a second, non-master descriptor (opened after the screen took
// master: the first opener of a card becomes its master).
struct CrtcState {
  std::uint32_t buffer_id = 0;
  int width = 0, height = 0;
};
CrtcState crtc_state() {
  UniqueFd fd = open_card("/dev/dri/card0");
  ModeResources res = get_resources(fd, "/dev/dri/card0");
  ModeCrtc crtc(drmModeGetCrtc(fd.get(), res->crtcs[0]));
  if (!crtc) return {};
  return {crtc->buffer_id, crtc->mode_valid ? crtc->mode.hdisplay : 0,
          crtc->mode_valid ? crtc->mode.vdisplay : 0};
}

TEST_F(VirtioGpu, PageFlipsShowEachFrameAtIncreasingVblankTimes) {
  constexpr int kFrames = 12;
  CrtcState before;
  std::vector<FlipEvent> flips;
  std::vector<TimestampNs> submitted, returned;
  const auto t0 = std::chrono::steady_clock::now();
  {
    KmsScreen screen(small_mode());
    before = crtc_state();
    EXPECT_EQ(screen.target().driver, "virtio_gpu");
    EXPECT_EQ(screen.target().connector.rfind("Virtual-", 0), 0u) << screen.target().connector;
    std::printf("screen: %s %s %s, GL_RENDERER %s\n", screen.target().card.c_str(),
                screen.target().connector.c_str(), to_string(screen.target().mode).c_str(),
                screen.renderer().c_str());
    const int w = screen.target().mode.width, h = screen.target().mode.height;
    for (int i = 0; i < kFrames; ++i) {
      submitted.push_back(monotonic_now_ns());
      const PresentResult r = screen.present(test_card(i));
      returned.push_back(monotonic_now_ns());
      std::printf("present %d: %.1f ms (draw %.1f, swap %.1f, show %.1f)\n", i,
                  static_cast<double>(returned.back() - submitted.back()) * 1e-6, r.draw_ms,
                  r.swap_ms, r.show_ms);
      if (i == 0) {
        EXPECT_TRUE(r.mode_set);
        EXPECT_FALSE(r.flip.has_value());
        const CrtcState now = crtc_state();
        EXPECT_EQ(now.width, w);
        EXPECT_EQ(now.height, h);
        EXPECT_NE(now.buffer_id, before.buffer_id) << "the CRTC still shows the console";
      } else {
        ASSERT_TRUE(r.flip.has_value()) << "frame " << i;
        flips.push_back(*r.flip);
      }
      // What the CRTC scans out: black bars, the red and blue halves with this frame's green.
      const auto r0 = monotonic_now_ns();
      const ImageRGB8 shown = screen.read_scanout();
      std::printf("read %d: %.1f ms\n", i, static_cast<double>(monotonic_now_ns() - r0) * 1e-6);
      ASSERT_EQ(shown.width(), w);
      ASSERT_EQ(shown.height(), h);
      const Viewport v = letterbox(320, 180, w, h);
      EXPECT_EQ(screen.last_viewport(), v);
      const int g = i * 7 % 256;
      expect_pixel(shown, v.x + v.width / 4, v.y + v.height / 2, 230, g, 0, "left half");
      expect_pixel(shown, v.x + 3 * v.width / 4, v.y + v.height / 2, 0, g, 230, "right half");
      if (v.x > 0) expect_pixel(shown, v.x / 2, h / 2, 0, 0, 0, "left bar");
      if (v.y > 0) expect_pixel(shown, w / 2, v.y / 2, 0, 0, 0, "top bar");
      if (::testing::Test::HasFailure()) return;
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Each flip's vblank falls between the call and its return, on CLOCK_MONOTONIC, and the
  // times increase: the event belongs to that flip, not to an earlier or a stale one.
  ASSERT_EQ(flips.size(), static_cast<std::size_t>(kFrames - 1));
  for (std::size_t i = 0; i < flips.size(); ++i) {
    EXPECT_GE(flips[i].timestamp_ns, submitted[i + 1]) << "flip " << i;
    EXPECT_LE(flips[i].timestamp_ns, returned[i + 1]) << "flip " << i;
    if (i > 0) {
      EXPECT_GT(flips[i].timestamp_ns, flips[i - 1].timestamp_ns);
      EXPECT_GE(flips[i].sequence, flips[i - 1].sequence);
    }
  }
  const double span_s =
      static_cast<double>(flips.back().timestamp_ns - flips.front().timestamp_ns) * 1e-9;
  std::printf(
      "%d frames in %.2f s; %zu flips over %.3f s: %.1f flips/s, vblank sequence %llu..%llu\n",
      kFrames, seconds, flips.size(), span_s, static_cast<double>(flips.size() - 1) / span_s,
      static_cast<unsigned long long>(flips.front().sequence),
      static_cast<unsigned long long>(flips.back().sequence));
  // The console's framebuffer is back on the CRTC once the screen is gone.
  const CrtcState after = crtc_state();
  EXPECT_EQ(after.buffer_id, before.buffer_id);
  EXPECT_EQ(after.width, before.width);
}

TEST_F(VirtioGpu, ARequestedModeIsSetAndAnUnofferedOneIsAClearError) {
  // A mode the connector offers that is not the preferred one: read the list first.
  std::string wanted;
  {
    UniqueFd fd = open_card("/dev/dri/card0");
    ModeResources res = get_resources(fd, "/dev/dri/card0");
    for (int i = 0; i < res->count_connectors && wanted.empty(); ++i) {
      ModeConnector c(drmModeGetConnector(fd.get(), res->connectors[i]));
      for (int m = 0; c && m < c->count_modes; ++m) {
        const ModeInfo info = mode_info(c->modes[m]);
        if (!info.preferred && info.width < 1024) {
          wanted = std::to_string(info.width) + "x" + std::to_string(info.height);
          break;
        }
      }
    }
  }
  ASSERT_FALSE(wanted.empty()) << "virtio-gpu offers only its preferred mode";
  {
    KmsScreenConfig config;
    config.card = "card0";
    config.mode = wanted;
    KmsScreen screen(config);
    ASSERT_EQ(to_string(ModeRequest{screen.target().mode.width, screen.target().mode.height, {}}),
              wanted);
    screen.present(test_card(1));
    const CrtcState now = crtc_state();
    EXPECT_EQ(std::to_string(now.width) + "x" + std::to_string(now.height), wanted);
    std::printf("mode %s set\n", wanted.c_str());
  }
  KmsScreenConfig config;
  config.mode = "1234x567@60";
  try {
    KmsScreen screen(config);
    FAIL() << "a mode the connector does not offer was accepted";
  } catch (const DisplayError& e) {
    EXPECT_NE(std::string(e.what()).find("mode 1234x567@60 is not offered by Virtual-1"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(VirtioGpu, AnUnknownConnectorNamesTheOnesThereAre) {
  KmsScreenConfig config;
  config.connector = "HDMI-A-1";
  try {
    KmsScreen screen(config);
    FAIL() << "an absent connector was accepted";
  } catch (const DisplayError& e) {
    EXPECT_NE(std::string(e.what()).find("no connector named HDMI-A-1 on card0 (it has: "
                                         "Virtual-1 (connected)"),
              std::string::npos)
        << e.what();
  }
  // Names match case-insensitively. The KMS half alone: no EGL start-up for a choice.
  KmsModeset modeset("", "virtual-1", std::nullopt);
  EXPECT_EQ(modeset.target().connector, "Virtual-1");
  // No mode asked: the connector's preferred one (QEMU's default 1280x800).
  EXPECT_TRUE(modeset.target().mode.preferred) << to_string(modeset.target().mode);
}

// What `probeless devices` lists: the card, its one virtual connector, plugged in, with
// QEMU's 1280x800 preferred among the standard modes.
TEST_F(VirtioGpu, TheInventoryListsTheCardConnectorAndModes) {
  const auto cards = list_displays();
  ASSERT_EQ(cards.size(), 1u);
  EXPECT_EQ(cards[0].path, "/dev/dri/card0");
  EXPECT_EQ(cards[0].driver, "virtio_gpu");
  EXPECT_TRUE(cards[0].error.empty()) << cards[0].error;
  ASSERT_EQ(cards[0].connectors.size(), 1u);
  const auto& c = cards[0].connectors[0];
  EXPECT_EQ(c.info.name, "Virtual-1");
  EXPECT_TRUE(c.info.connected);
  ASSERT_GT(c.modes.size(), 5u);
  int preferred = 0;
  for (const auto& m : c.modes)
    if (m.preferred) {
      ++preferred;
      EXPECT_EQ(to_string(m).rfind("1280x800@", 0), 0u) << to_string(m);
    }
  EXPECT_EQ(preferred, 1);
}

TEST_F(VirtioGpu, ASecondMasterIsToldTheCardIsBusy) {
  KmsScreen first(small_mode());
  first.present(test_card(0));
  try {
    KmsScreen second(small_mode());
    FAIL() << "a second screen on a card with a master was opened";
  } catch (const DisplayError& e) {
    EXPECT_NE(std::string(e.what()).find("card0 is busy: another process is its DRM master"),
              std::string::npos)
        << e.what();
  }
  // The first screen is unaffected.
  EXPECT_TRUE(first.present(test_card(1)).flip.has_value());
}

TEST_F(VirtioGpu, TheDisplayOutputFlipsSubmittedFramesOnItsOwnThread) {
  KmsDisplayConfig config;
  config.screen = small_mode();
  KmsDisplay display(config);
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  int i = 0;
  while (display.stats().flips < 8 && std::chrono::steady_clock::now() < deadline) {
    // Submitted as if just captured: capture_to_flip is then the display path's own time.
    display.submit(std::make_shared<const ImageRGB8>(test_card(i++, 640, 360)), monotonic_now_ns());
    std::this_thread::sleep_for(20ms);  // faster than the display: some frames are dropped
  }
  const KmsDisplayStats s = display.stats();
  std::printf(
      "display output: %llu in, %llu shown, %llu flips, %llu dropped, %.1f flips/s, "
      "last interval %.1f ms, submit to flip p50 %.1f ms p99 %.1f ms\n",
      static_cast<unsigned long long>(s.frames_in), static_cast<unsigned long long>(s.frames_shown),
      static_cast<unsigned long long>(s.flips), static_cast<unsigned long long>(s.dropped),
      s.flips_per_s, s.last_flip_interval_ms, s.capture_to_flip.p50_ms, s.capture_to_flip.p99_ms);
  EXPECT_EQ(s.state, "showing") << s.last_error;
  // The flip's vblank time is on CLOCK_MONOTONIC, as the capture times are: positive, and
  // within the 20 s the loop may take.
  EXPECT_GT(s.capture_to_flip.p50_ms, 0);
  EXPECT_LT(s.capture_to_flip.p99_ms, 20000);
  EXPECT_GE(s.flips, 8u);
  EXPECT_GT(s.dropped, 0u);
  EXPECT_EQ(s.mode.rfind("640x480@", 0), 0u) << s.mode;
  EXPECT_EQ(s.connector, "Virtual-1");
  EXPECT_GT(s.flips_per_s, 0);
  EXPECT_TRUE(s.last_error.empty()) << s.last_error;
  const auto j = display.status();
  EXPECT_EQ(j["connector"], "Virtual-1");
  EXPECT_EQ(j["capture_to_flip"]["p50_ms"], s.capture_to_flip.p50_ms);
  display.stop();
  EXPECT_EQ(crtc_state().width, 1280) << "the console's 1280x800 is not back";
}

}  // namespace
}  // namespace probeless::display
