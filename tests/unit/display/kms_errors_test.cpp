// The tethered display's errors that need no display device: a machine without a KMS card,
// a card that is not there, a file that is not DRM, a bad mode in the config, and the
// display output that keeps retrying with the reason in its status rather than failing the
// service. The device paths themselves are tested on virtio-gpu (tests/vm/check_kms.sh).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "app/outputs/display/drm_inventory.hpp"
#include "app/outputs/display/kms_modeset.hpp"
#include "app/outputs/kms_display.hpp"
#include "app/pipeline/service_config.hpp"
#include "core/error.hpp"
#include "support/test_data.hpp"

namespace probeless::display {
namespace {

using namespace std::chrono_literals;

std::string open_error(const std::string& card, const std::filesystem::path& dri_dir,
                       const std::string& connector = "") {
  try {
    KmsModeset m(card, connector, std::nullopt, dri_dir);
    return "(opened " + m.target().card.string() + ")";
  } catch (const DisplayError& e) {
    return e.what();
  }
}

TEST(KmsErrors, NoCardAtAllSaysNoKmsDriverIsLoaded) {
  const auto dir = testing::scratch_dir();
  EXPECT_EQ(open_error("", dir),
            "no " + dir.string() +
                "/card*: no KMS display driver is loaded (a board's vc4/rockchip/i915, or "
                "virtio-gpu in a VM)");
  EXPECT_EQ(open_error("", dir / "missing").find("no " + (dir / "missing").string() + "/card*"),
            0u);
  // renderD* nodes are not cards: a render-only GPU does not count as a display.
  std::ofstream(dir / "renderD128").put('x');
  EXPECT_TRUE(list_cards(dir).empty());
}

TEST(KmsErrors, ANamedCardThatIsNotThere) {
  const auto dir = testing::scratch_dir();
  EXPECT_EQ(open_error("card3", dir),
            "no DRM device " + (dir / "card3").string() + " (no KMS driver bound to it)");
  EXPECT_EQ(open_error("/nonexistent/card0", dir),
            "no DRM device /nonexistent/card0 (no KMS driver bound to it)");
}

TEST(KmsErrors, AFileThatIsNotADrmDevice) {
  const std::string e = open_error("/dev/null", "/dev/dri");
  EXPECT_EQ(e.find("/dev/null is not a KMS display device (drmModeGetResources: "), 0u) << e;
  // Found by the scan too: each card's reason is reported.
  const auto dir = testing::scratch_dir();
  std::ofstream(dir / "card0").put('x');
  std::ofstream(dir / "card10").put('x');
  std::ofstream(dir / "card2").put('x');
  const auto cards = list_cards(dir);
  ASSERT_EQ(cards.size(), 3u);
  EXPECT_EQ(cards[0].filename(), "card0");
  EXPECT_EQ(cards[1].filename(), "card2");  // numeric order, not card10 before card2
  EXPECT_EQ(cards[2].filename(), "card10");
  const std::string all = open_error("", dir);
  EXPECT_NE(all.find("card0 is not a KMS display device"), std::string::npos) << all;
  EXPECT_NE(all.find("card10 is not a KMS display device"), std::string::npos) << all;
}

TEST(DisplayInventory, ListsUnreadableCardsWithTheReason) {
  const auto dir = testing::scratch_dir();
  EXPECT_TRUE(list_displays(dir).empty());
  std::ofstream(dir / "card0").put('x');
  const auto cards = list_displays(dir);
  ASSERT_EQ(cards.size(), 1u);
  EXPECT_EQ(cards[0].path, dir / "card0");
  EXPECT_NE(cards[0].error.find("is not a KMS display device"), std::string::npos)
      << cards[0].error;
  EXPECT_TRUE(cards[0].connectors.empty());
}

TEST(KmsErrors, CardPathsByNameOrPath) {
  EXPECT_EQ(card_path("card1", "/dev/dri"), "/dev/dri/card1");
  EXPECT_EQ(card_path("/dev/dri/by-path/platform-gpu-card", "/dev/dri"),
            "/dev/dri/by-path/platform-gpu-card");
}

TEST(KmsDisplayOutput, ABadModeFailsAtConstruction) {
  KmsDisplayConfig config;
  config.screen.mode = "fullhd";
  EXPECT_THROW(KmsDisplay display(config), DisplayError);
}

TEST(KmsDisplayOutput, NoScreenIsRetriedWithTheReasonInStatusWithoutBlockingSubmit) {
  KmsDisplayConfig config;
  config.screen.dri_dir = testing::scratch_dir();
  config.retry_every = 50ms;
  KmsDisplay display(config);
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (display.stats().state != "error" && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(5ms);
  for (int i = 0; i < 100; ++i) display.submit(std::make_shared<const ImageRGB8>(8, 8));
  const auto s = display.stats();
  EXPECT_EQ(s.state, "error");
  EXPECT_NE(s.last_error.find("no KMS display driver is loaded"), std::string::npos)
      << s.last_error;
  EXPECT_EQ(s.frames_in, 100u);
  EXPECT_EQ(s.flips, 0u);
  const auto j = display.status();
  EXPECT_EQ(j["state"], "error");
  EXPECT_EQ(j["flips_per_s"], 0.0);
  const auto t0 = std::chrono::steady_clock::now();
  display.stop();  // the retry wait ends at once
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s);
}

TEST(DisplayConfig, TheDisplaySectionIsParsedAndItsModeChecked) {
  const ServiceConfig off = parse_service_config("");
  EXPECT_FALSE(off.display.enabled);
  const ServiceConfig c = parse_service_config(
      "[display]\nenabled = true\ncard = \"card1\"\nconnector = \"HDMI-A-1\"\n"
      "mode = \"1920x1080@60\"\n");
  EXPECT_TRUE(c.display.enabled);
  EXPECT_EQ(c.display.screen.card, "card1");
  EXPECT_EQ(c.display.screen.connector, "HDMI-A-1");
  EXPECT_EQ(c.display.screen.mode, "1920x1080@60");
  try {
    parse_service_config("[display]\nenabled = true\nmode = \"1080p\"\n", "svc.toml");
    FAIL() << "a bad mode was accepted";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("display mode \"1080p\": expected WIDTHxHEIGHT"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_service_config("[display]\nconector = \"HDMI-A-1\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[display]\nenabled = \"yes\"\n"), ParseError);
}

}  // namespace
}  // namespace probeless::display
