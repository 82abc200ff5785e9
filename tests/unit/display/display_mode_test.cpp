// The device-free rules of the tethered display (app/outputs/display/display_mode.hpp): the
// config's mode string, which mode and connector are chosen, and the letterbox.
#include "app/outputs/display/display_mode.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace probeless::display {
namespace {

std::string error_of(auto&& f) {
  try {
    f();
  } catch (const DisplayError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ModeRequest, SizeAndOptionalRate) {
  const ModeRequest a = parse_mode_request("1920x1080");
  EXPECT_EQ(a.width, 1920);
  EXPECT_EQ(a.height, 1080);
  EXPECT_FALSE(a.refresh_hz.has_value());
  const ModeRequest b = parse_mode_request("1280x720@59.94");
  EXPECT_EQ(b.width, 1280);
  EXPECT_EQ(b.height, 720);
  ASSERT_TRUE(b.refresh_hz.has_value());
  EXPECT_DOUBLE_EQ(*b.refresh_hz, 59.94);
  EXPECT_EQ(to_string(b), "1280x720@59.94");
  EXPECT_EQ(to_string(parse_mode_request("640x480@60")), "640x480@60");
}

TEST(ModeRequest, MalformedStringsSayWhatIsExpected) {
  for (const char* bad :
       {"", "1920", "1920x", "x1080", "1920x1080@", "1920x1080@abc", "1920X1080", "-1x5", "0x480",
        "1920x1080@0", "1920x1080@60Hz", "1920 x 1080", "99999x1080", "1920x1080@60@30"}) {
    const std::string e = error_of([&] { parse_mode_request(bad); });
    EXPECT_NE(e.find("expected WIDTHxHEIGHT or WIDTHxHEIGHT@HZ"), std::string::npos)
        << "\"" << bad << "\": " << e;
  }
}

// As virtio-gpu lists them: the preferred mode first, then the standard modes.
const std::vector<ModeInfo> kModes{{1280, 800, 74.99, true},  {1920, 1080, 60.0, false},
                                   {1920, 1080, 50.0, false}, {1280, 720, 59.94, false},
                                   {1280, 720, 60.0, false},  {800, 600, 60.32, false}};

TEST(ChooseMode, PreferredWithoutARequest) {
  EXPECT_EQ(choose_mode(kModes, std::nullopt, "Virtual-1"), 0u);
  // No mode marked preferred: the first listed, the kernel's best.
  const std::vector<ModeInfo> none{{1024, 768, 60, false}, {800, 600, 60, false}};
  EXPECT_EQ(choose_mode(none, std::nullopt, "HDMI-A-1"), 0u);
}

TEST(ChooseMode, SizeTakesTheFastestRateAndARateMatchesWithinHalfAHertz) {
  EXPECT_EQ(choose_mode(kModes, parse_mode_request("1920x1080"), "c"), 1u);
  EXPECT_EQ(choose_mode(kModes, parse_mode_request("1920x1080@50"), "c"), 2u);
  EXPECT_EQ(choose_mode(kModes, parse_mode_request("1280x720@59.94"), "c"), 3u);
  EXPECT_EQ(choose_mode(kModes, parse_mode_request("1280x720@60"), "c"), 4u);  // the closest
  EXPECT_EQ(choose_mode(kModes, parse_mode_request("1280x720@59.8"), "c"), 3u);
  EXPECT_EQ(choose_mode(kModes, parse_mode_request("800x600@60"), "c"), 5u);
  // A size whose preferred mode is not its fastest: the preferred one.
  const std::vector<ModeInfo> tv{{1920, 1080, 30, false}, {1920, 1080, 24, true}};
  EXPECT_EQ(choose_mode(tv, parse_mode_request("1920x1080"), "c"), 1u);
}

TEST(ChooseMode, AModeNotOfferedListsWhatIs) {
  const std::string e =
      error_of([] { choose_mode(kModes, parse_mode_request("1920x1080@144"), "HDMI-A-1"); });
  EXPECT_NE(e.find("mode 1920x1080@144 is not offered by HDMI-A-1"), std::string::npos) << e;
  EXPECT_NE(e.find("1280x800@74.99 (preferred), 1920x1080@60.00"), std::string::npos) << e;
  EXPECT_NE(error_of([] {
              choose_mode(kModes, parse_mode_request("3840x2160"), "c");
            }).find("mode 3840x2160 is not offered"),
            std::string::npos);
  EXPECT_NE(error_of([] { choose_mode({}, std::nullopt, "DSI-1"); }).find("DSI-1 offers no modes"),
            std::string::npos);
}

const std::vector<ConnectorInfo> kConnectors{
    {"HDMI-A-1", false}, {"HDMI-A-2", true}, {"DSI-1", true}};

TEST(ChooseConnector, FirstConnectedOrTheNamedOne) {
  EXPECT_EQ(choose_connector(kConnectors, "", "card0"), 1u);
  EXPECT_EQ(choose_connector(kConnectors, "DSI-1", "card0"), 2u);
  EXPECT_EQ(choose_connector(kConnectors, "hdmi-a-2", "card0"), 1u);
}

TEST(ChooseConnector, UnknownDisconnectedOrNoneConnectedAreClearErrors) {
  std::string e = error_of([] { choose_connector(kConnectors, "Virtual-1", "card1"); });
  EXPECT_EQ(e,
            "no connector named Virtual-1 on card1 (it has: HDMI-A-1 (disconnected), "
            "HDMI-A-2 (connected), DSI-1 (connected))");
  e = error_of([] { choose_connector(kConnectors, "HDMI-A-1", "card1"); });
  EXPECT_NE(e.find("connector HDMI-A-1 on card1 is not connected"), std::string::npos) << e;
  const std::vector<ConnectorInfo> unplugged{{"HDMI-A-1", false}};
  e = error_of([&] { choose_connector(unplugged, "", "card0"); });
  EXPECT_EQ(e, "no connected connector on card0 (it has: HDMI-A-1 (disconnected))");
  e = error_of([] { choose_connector({}, "", "card0"); });
  EXPECT_EQ(e, "no connected connector on card0 (it has: none)");
}

TEST(Letterbox, KeepsTheAspectRatioCentredWithBlackBars) {
  EXPECT_EQ(letterbox(640, 480, 1920, 1080), (Viewport{240, 0, 1440, 1080}));  // bars left/right
  EXPECT_EQ(letterbox(1920, 1080, 640, 480), (Viewport{0, 60, 640, 360}));     // top/bottom
  EXPECT_EQ(letterbox(1280, 720, 1920, 1080), (Viewport{0, 0, 1920, 1080}));   // same aspect
  EXPECT_EQ(letterbox(320, 240, 1280, 800), (Viewport{106, 0, 1067, 800}));    // rounded
  EXPECT_EQ(letterbox(100, 100, 101, 50), (Viewport{25, 0, 50, 50}));
  // Degenerate input never gives a negative or larger-than-screen viewport.
  EXPECT_EQ(letterbox(0, 480, 640, 480), (Viewport{0, 0, 640, 480}));
}

TEST(Letterbox, FitsInsideTheScreenForAnySizes) {
  for (int iw : {1, 3, 317, 640, 1919, 4000})
    for (int ih : {1, 2, 239, 480, 1081, 3000})
      for (auto [sw, sh] : {std::pair{640, 480}, {1920, 1080}, {801, 601}, {1080, 1920}}) {
        const Viewport v = letterbox(iw, ih, sw, sh);
        ASSERT_GE(v.x, 0);
        ASSERT_GE(v.y, 0);
        ASSERT_LE(v.x + v.width, sw);
        ASSERT_LE(v.y + v.height, sh);
        // One axis is filled, and the aspect ratio is kept to within a pixel of rounding.
        ASSERT_TRUE(v.width == sw || v.height == sh)
            << iw << "x" << ih << " in " << sw << "x" << sh;
        const double err =
            std::abs(static_cast<double>(v.width) * ih - static_cast<double>(v.height) * iw);
        ASSERT_LE(err, std::max(iw, ih)) << iw << "x" << ih << " in " << sw << "x" << sh;
      }
}

}  // namespace
}  // namespace probeless::display
