// `probeless eval sh` as a user runs it: the real binary, its JSON, its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/latlong.hpp"
#include "core/sh.hpp"
#include "drivers/io/hdr_image.hpp"
#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

// Runs probeless with `args`; returns the exit status (-1 on timeout). `output` gets stdout
// and stderr.
int run(const std::vector<std::string>& args, std::string* output = nullptr) {
  return testing::run_to_end(testing::probeless_binary(), args, output, 120s);
}

// Ramamoorthi & Hanrahan's Uffizi row, against the command's y-up output of the probe / 10
// (../shared/data/sh-reference/VERIFICATION.txt): all 27 numbers within 0.002.
TEST(EvalSh, UffiziMatchesThePublishedCoefficients) {
  PROBELESS_REQUIRE_DATA("hdr/probes/uffizi.hdr");
  PROBELESS_REQUIRE_DATA("sh-reference/orange_book_sh9_irradiance_coeffs.csv");
  const auto data = testing::shared_data_dir();
  std::ifstream csv(data / "sh-reference/orange_book_sh9_irradiance_coeffs.csv");
  std::map<std::string, std::array<double, 3>> table;
  for (std::string line; std::getline(csv, line);) {
    if (!line.starts_with("UffiziGallery,")) continue;
    std::stringstream row(line);
    std::string env, name, r, g, b;
    std::getline(row, env, ',');
    std::getline(row, name, ',');
    std::getline(row, r, ',');
    std::getline(row, g, ',');
    std::getline(row, b, ',');
    table[name] = {std::stod(r), std::stod(g), std::stod(b)};
  }
  ASSERT_EQ(table.size(), 9u);

  const auto out = testing::scratch_dir() / "uffizi.json";
  std::string output;
  ASSERT_EQ(run({"eval", "sh", "--probe", (data / "hdr/probes/uffizi.hdr").string(), "--scale",
                 "0.1", "--convention", "y-up", "--json", out.string()},
                &output),
            0)
      << output;
  std::ifstream in(out);
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j.at("sh9").size(), 9u);
  ASSERT_EQ(j.at("sh25").size(), 25u);
  EXPECT_TRUE(j.at("convention").get<std::string>().starts_with("y-up"));
  const char* names[9] = {"L00", "L1m1", "L10", "L11", "L2m2", "L2m1", "L20", "L21", "L22"};
  double worst = 0;
  for (int i = 0; i < 9; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double ours = j["sh9"][i][c].get<double>();
      EXPECT_NEAR(ours, table.at(names[i])[c], 0.002) << names[i] << " channel " << c;
      EXPECT_EQ(ours, j["sh25"][i][c].get<double>());  // sh9 is the head of sh25
      worst = std::max(worst, std::abs(ours - table.at(names[i])[c]));
    }
  }
  EXPECT_EQ(j.at("names")[4].get<std::string>(), "L2-2");
  std::cout << "[ INFO     ] eval sh, Uffizi vs R&H: max abs difference " << worst << "\n";
}

// A probe that is a single harmonic in the world frame (z-up): the command returns it alone.
TEST(EvalSh, RecoversASingleHarmonicInTheWorldFrame) {
  const int w = 256, h = 128;
  ImageRGBF probe(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const ShBasis b = sh_basis(latlong_pixel_direction(x, y, w, h));
      probe.at(x, y, 0) = static_cast<float>(1.0 + 0.5 * b[sh_index(1, 0)]);   // z: up
      probe.at(x, y, 1) = static_cast<float>(1.0 + 0.5 * b[sh_index(2, -2)]);  // xy
      probe.at(x, y, 2) = 1.0f;
    }
  }
  const auto dir = testing::scratch_dir();
  write_hdr_image(dir / "probe.exr", probe);
  ASSERT_EQ(run({"eval", "sh", "--probe", (dir / "probe.exr").string(), "--json",
                 (dir / "out.json").string()}),
            0);
  std::ifstream in(dir / "out.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_TRUE(j.at("convention").get<std::string>().starts_with("z-up"));
  const double dc = std::sqrt(4.0 * 3.14159265358979);  // 1 = sqrt(4 pi) Y00
  for (int i = 0; i < 25; ++i) {
    const double r = i == 0 ? dc : i == sh_index(1, 0) ? 0.5 : 0.0;
    const double g = i == 0 ? dc : i == sh_index(2, -2) ? 0.5 : 0.0;
    const double b = i == 0 ? dc : 0.0;
    EXPECT_NEAR(j["sh25"][i][0].get<double>(), r, 2e-3) << i;
    EXPECT_NEAR(j["sh25"][i][1].get<double>(), g, 2e-3) << i;
    EXPECT_NEAR(j["sh25"][i][2].get<double>(), b, 2e-3) << i;
  }
}

TEST(EvalSh, BadInputsFailWithAClearMessage) {
  const auto dir = testing::scratch_dir();
  std::string output;
  // Missing file.
  EXPECT_EQ(run({"eval", "sh", "--probe", (dir / "missing.hdr").string()}, &output), 1);
  EXPECT_NE(output.find("missing.hdr: cannot open"), std::string::npos) << output;
  // Not an image.
  { std::ofstream(dir / "text.hdr") << "this is not a Radiance file\n"; }
  EXPECT_EQ(run({"eval", "sh", "--probe", (dir / "text.hdr").string()}, &output), 1);
  EXPECT_NE(output.find("text.hdr: not a Radiance HDR file"), std::string::npos) << output;
  // Not 2:1.
  write_hdr_image(dir / "square.hdr", ImageRGBF(64, 64, 1.0f));
  EXPECT_EQ(run({"eval", "sh", "--probe", (dir / "square.hdr").string(), "--json",
                 (dir / "square.json").string()},
                &output),
            1);
  EXPECT_NE(output.find("64x64 is not a latitude-longitude map"), std::string::npos) << output;
  EXPECT_FALSE(std::filesystem::exists(dir / "square.json"));
  // Bad scale and convention.
  write_hdr_image(dir / "ok.hdr", ImageRGBF(64, 32, 1.0f));
  EXPECT_EQ(run({"eval", "sh", "--probe", (dir / "ok.hdr").string(), "--scale", "0"}), 1);
  EXPECT_NE(run({"eval", "sh", "--probe", (dir / "ok.hdr").string(), "--convention", "x-up"}), 0);
  EXPECT_EQ(run({"eval", "sh", "--probe", (dir / "ok.hdr").string()}), 0);
}

}  // namespace
}  // namespace probeless
