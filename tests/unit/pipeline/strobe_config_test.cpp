// [bracket]'s strobe keys (docs/configuration.md): the strobe input whose edges stamp the
// fisheye frames.
#include <gtest/gtest.h>

#include "app/pipeline/service_config.hpp"
#include "core/error.hpp"

namespace probeless {
namespace {

TEST(StrobeConfig, OffByDefault) {
  const ServiceConfig c = parse_service_config("");
  EXPECT_EQ(c.strobe_chip, "");
  EXPECT_EQ(c.strobe_line, 0);
  EXPECT_EQ(c.strobe_edge, "rising");
}

TEST(StrobeConfig, ReadsChipLineAndEdge) {
  const ServiceConfig c = parse_service_config(R"(
[bracket]
gpio_chip = "pinctrl-rp1"
gpio_line = 17
strobe_chip = "pinctrl-rp1"
strobe_line = 27
strobe_edge = "falling"
)");
  EXPECT_EQ(c.trigger_chip, "pinctrl-rp1");
  EXPECT_EQ(c.strobe_chip, "pinctrl-rp1");
  EXPECT_EQ(c.strobe_line, 27);
  EXPECT_EQ(c.strobe_edge, "falling");
}

TEST(StrobeConfig, BadValuesAreErrorsNamingTheKey) {
  try {
    parse_service_config("[bracket]\nstrobe_edge = \"up\"\n", "board.toml");
    FAIL() << "accepted strobe_edge = up";
  } catch (const ParseError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("board.toml"), std::string::npos) << what;
    EXPECT_NE(what.find("'up'"), std::string::npos) << what;
  }
  EXPECT_THROW(parse_service_config("[bracket]\nstrobe_line = -2\n"), ParseError);
  EXPECT_THROW(parse_service_config("[bracket]\nstrobe_line = \"27\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[bracket]\nstrobe_pin = 27\n"), ParseError);
}

}  // namespace
}  // namespace probeless
