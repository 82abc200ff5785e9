// The strobe input and the chip list without a GPIO chip: what this machine can check (the
// edges themselves are tested on gpio-sim in a VM, tests/vm/gpio_sim_test.cpp).
#include "drivers/trigger/gpio_strobe.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "drivers/trigger/gpio_chips.hpp"

namespace probeless {
namespace {

TEST(StrobeEdge, ParsesTheThreeEdgesAndNamesThemBack) {
  for (const StrobeEdge edge : {StrobeEdge::Rising, StrobeEdge::Falling, StrobeEdge::Both})
    EXPECT_EQ(parse_strobe_edge(to_string(edge)), edge);
  EXPECT_EQ(parse_strobe_edge("rising"), StrobeEdge::Rising);
}

TEST(StrobeEdge, AnythingElseIsAnErrorQuotingIt) {
  for (const char* bad : {"", "Rising", "up", "rising "}) {
    try {
      parse_strobe_edge(bad);
      FAIL() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + std::string(bad) + "'"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("\"both\""), std::string::npos) << e.what();
    }
  }
}

TEST(GpioStrobe, MissingChipIsAClearError) {
  GpioStrobeConfig config;
  config.chip = "probeless-no-such-gpiochip";
  config.line = 3;
  try {
    GpioStrobe strobe(config);
    FAIL() << "opened " << strobe.name();
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("gpio strobe"), std::string::npos) << what;
    EXPECT_NE(what.find("'probeless-no-such-gpiochip'"), std::string::npos) << what;
  }
}

class ChipDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("probeless-gpio-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(ChipDir, NoChipGivesAnEmptyList) {
  std::ofstream(dir_ / "ttyS0") << "";
  EXPECT_TRUE(list_gpio_chips(dir_).empty());
  EXPECT_TRUE(list_gpio_chips(dir_ / "missing").empty());
}

// A file named like a chip that is not one (or one this user may not open) is listed with
// the reason, in number order, rather than dropped or fatal.
TEST_F(ChipDir, AnUnopenableChipIsListedWithItsError) {
  std::ofstream(dir_ / "gpiochip10") << "";
  std::ofstream(dir_ / "gpiochip9") << "";
  const auto chips = list_gpio_chips(dir_);
  ASSERT_EQ(chips.size(), 2u);
  EXPECT_EQ(chips[0].name, "gpiochip9");
  EXPECT_EQ(chips[1].name, "gpiochip10");
  for (const auto& c : chips) {
    EXPECT_FALSE(c.error.empty()) << c.path;
    EXPECT_EQ(c.lines, 0u);
  }
}

}  // namespace
}  // namespace probeless
