#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>

#include "core/error.hpp"
#include "drivers/replay/text_fields.hpp"

namespace probeless::replay {
namespace {

const TextLocation kWhere{"index.csv", 7};

TEST(TextFields, DoublesRoundTripBitForBit) {
  std::mt19937_64 rng(42);
  for (int i = 0; i < 20000; ++i) {
    const double v = std::bit_cast<double>(rng());
    if (!std::isfinite(v)) continue;
    const double back = parse_double(format_double(v), kWhere, "value");
    EXPECT_EQ(std::bit_cast<std::uint64_t>(back), std::bit_cast<std::uint64_t>(v)) << v;
  }
  for (double v : {0.0, -0.0, 0.1, 1e-300, 5e-324, std::numeric_limits<double>::max(), 0.016666666666666666}) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(parse_double(format_double(v), kWhere, "v")),
              std::bit_cast<std::uint64_t>(v));
  }
  EXPECT_EQ(format_double(0.01), "0.01");
}

TEST(TextFields, BadNumbersNameFileAndLine) {
  for (const char* bad : {"", "1.5x", "abc", "nan", "inf", " 1"}) {
    try {
      (void)parse_double(bad, kWhere, "gain_db");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.source(), "index.csv");
      EXPECT_EQ(e.line(), 7);
      EXPECT_NE(std::string(e.what()).find("index.csv:7: bad gain_db"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW((void)parse_int64("12a", kWhere, "t"), ParseError);
  EXPECT_THROW((void)parse_uint64("-1", kWhere, "sequence"), ParseError);
  EXPECT_THROW((void)parse_int64("99999999999999999999", kWhere, "t"), ParseError);
  EXPECT_EQ(parse_int64("-42", kWhere, "t"), -42);
  EXPECT_THROW((void)parse_int_in("17", 1, 16, kWhere, "bit_depth"), ParseError);
  EXPECT_EQ(parse_int_in("16", 1, 16, kWhere, "bit_depth"), 16);
}

TEST(TextFields, SecondsAreExactNanoseconds) {
  for (TimestampNs t : {TimestampNs{0}, TimestampNs{1}, TimestampNs{999'999'999},
                        TimestampNs{1'305'031'102'175'304'000}, TimestampNs{-1'500'000'000},
                        std::numeric_limits<TimestampNs>::max() / 2}) {
    EXPECT_EQ(parse_seconds(format_seconds(t), kWhere), t) << format_seconds(t);
  }
  EXPECT_EQ(format_seconds(12'000'000'345), "12.000000345");
  EXPECT_EQ(parse_seconds("1305031102.175304", kWhere), 1'305'031'102'175'304'000);
  EXPECT_EQ(parse_seconds("3", kWhere), 3'000'000'000);
  EXPECT_EQ(parse_seconds(".5", kWhere), 500'000'000);
  EXPECT_EQ(parse_seconds("1.0000000015", kWhere), 1'000'000'002);  // rounded
  for (const char* bad : {"", ".", "1.2.3", "1e9", "12:30", "-", "99999999999999999999"}) {
    EXPECT_THROW((void)parse_seconds(bad, kWhere), ParseError) << bad;
  }
}

TEST(TextFields, Splitting) {
  EXPECT_EQ(split_fields("a,,b,", ',').size(), 4u);
  EXPECT_EQ(split_fields("", ',').size(), 1u);
  const auto w = split_whitespace("  1.0\t rgb/1.png  ");
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0], "1.0");
  EXPECT_EQ(w[1], "rgb/1.png");
}

}  // namespace
}  // namespace probeless::replay
