// The simulated camera, the hat-weighted merge and `probeless eval hdr`, end to end on a small
// synthetic HDR image (docs/bracketing.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "drivers/bracket/bracket_simulation.hpp"
#include "drivers/io/hdr_image.hpp"
#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

// A horizontal ramp in log radiance over 2^16 (~6.6e4:1), tinted per row band.
ImageRGBF synthetic_hdr(int w = 96, int h = 24) {
  ImageRGBF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float r = std::exp2(16.0f * static_cast<float>(x) / static_cast<float>(w - 1) - 8.0f);
      img.at(x, y, 0) = r;
      img.at(x, y, 1) = r * (y < h / 2 ? 0.8f : 0.5f);
      img.at(x, y, 2) = r * 0.6f;
    }
  return img;
}

TEST(SimulatedCamera, NoiseFreeValuesAreTheRoundedSignalOverBlack) {
  SimulatedCameraModel cam = SimulatedCameraModel::for_bits(8);
  cam.full_well_e = 1e15;
  cam.read_noise_dn = 0;
  cam.scale = 1000.0;
  ImageRGBF img(3, 1);
  img.at(0, 0, 0) = 1.0f;   // 1 * 0.01 * 1000 = 10 DN
  img.at(1, 0, 0) = 50.0f;  // 500 DN: saturated
  img.at(2, 0, 0) = 0.02f;  // 0.2 DN: rounds to black
  std::mt19937_64 rng(1);
  const ImageRGB16 raw = simulate_capture(img, Exposure{0.01, 0.0}, cam, rng);
  EXPECT_EQ(raw.at(0, 0, 0), 16 + 10);
  EXPECT_EQ(raw.at(1, 0, 0), 255);
  EXPECT_EQ(raw.at(2, 0, 0), 16);
}

TEST(SimulatedCamera, ShotNoiseGrowsWithGain) {
  SimulatedCameraModel cam = SimulatedCameraModel::for_bits(12);
  cam.read_noise_dn = 0;
  cam.scale = 1.0;
  ImageRGBF img(200, 200, 1000.0f);  // 1000 DN at E = 1
  auto stddev = [&](const Exposure& e) {
    std::mt19937_64 rng(7);
    const ImageRGB16 raw = simulate_capture(img, e, cam, rng);
    double s = 0, s2 = 0;
    for (auto v : raw.elements()) {
      s += v;
      s2 += double(v) * v;
    }
    const double n = static_cast<double>(raw.elements().size());
    return std::sqrt(s2 / n - (s / n) * (s / n));
  };
  // 1000 DN = 1000 * 10000 / 3839 e- at 0 dB: sigma = sqrt(1000 * 3839 / 10000) = 19.6 DN.
  EXPECT_NEAR(stddev(Exposure{1.0, 0.0}), 19.6, 0.5);
  // The same DN at x4 gain comes from a quarter of the electrons: twice the noise.
  EXPECT_NEAR(stddev(Exposure{0.25, gain_db_from_linear(4.0)}), 39.2, 1.0);
}

TEST(MergeBracket, HatWeightedMeanOfValidSamples) {
  SimulatedCameraModel cam = SimulatedCameraModel::for_bits(8);  // black 16, range 239
  cam.scale = 1.0;
  std::vector<BracketFrame> frames(3);
  const std::uint16_t values[3] = {255, 16 + 60, 16 + 100};  // saturated, x = .251, x = .418
  const double e[3] = {4.0, 1.0, 1.6};
  for (int i = 0; i < 3; ++i) {
    frames[i].stamp.exposure = Exposure{e[i], 0.0};
    frames[i].raw = ImageRGB16(2, 1, 16);  // pixel 1 all black: unmeasured
    for (int c = 0; c < 3; ++c) frames[i].raw.at(0, 0, c) = values[i];
  }
  ImageGray8 measured;
  const ImageRGBF merged = merge_bracket(frames, cam, &measured);
  const double w1 = 60.0 / 239, w2 = 100.0 / 239;
  EXPECT_NEAR(merged.at(0, 0, 0), (w1 * 60.0 + w2 * 100.0 / 1.6) / (w1 + w2), 1e-4);
  EXPECT_EQ(measured.at(0, 0), 255);
  EXPECT_EQ(measured.at(1, 0), 0);
  EXPECT_EQ(merged.at(1, 0, 0), 0.0f);
}

TEST(EvalHdr, SyntheticImageSettlesAndMergesAccurately) {
  const ImageRGBF img = synthetic_hdr();
  HdrEvalOptions opts;
  opts.bits = 12;
  opts.cycles = 12;
  opts.full_well_e = 1e12;  // quantisation and read noise only: the sequencer and the merge
  const HdrEvalReport r = evaluate_bracketing(img, opts);
  EXPECT_TRUE(r.settled);
  EXPECT_LE(r.settle_cycles, 8);
  EXPECT_GT(r.measurable_fraction, 0.97);
  EXPECT_LT(r.median_rel_error, 0.01);
  EXPECT_LT(r.p95_rel_error, 1.0);  // the darkest columns sit a few DN above black
  EXPECT_GE(r.medium_stop - r.low_stop, 1);
  EXPECT_GE(r.high_stop - r.medium_stop, 1);

  opts.full_well_e = 0;  // the default noisy camera, both depths
  for (int bits : {8, 12}) {
    opts.bits = bits;
    const HdrEvalReport noisy = evaluate_bracketing(img, opts);
    EXPECT_TRUE(noisy.settled) << bits;
    EXPECT_LE(noisy.settle_cycles, 8) << bits;
    EXPECT_LT(noisy.median_rel_error, 0.05) << bits;
  }
}

TEST(EvalHdr, CommandWritesTheJsonReport) {
  const char* binary = std::getenv("PROBELESS_BINARY");
  if (!binary) GTEST_SKIP() << "PROBELESS_BINARY not set";
  const auto dir = testing::scratch_dir();
  write_hdr_image(dir / "ramp.hdr", synthetic_hdr());
  testing::Subprocess p({binary, "eval", "hdr", "--image", (dir / "ramp.hdr").string(), "--bits",
                         "12", "--cycles", "10", "--json", (dir / "out.json").string()});
  ASSERT_EQ(p.wait(std::chrono::seconds(120)), 0) << p.output();
  std::ifstream in(dir / "out.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("bits").get<int>(), 12);
  EXPECT_EQ(j.at("image").get<std::string>(), (dir / "ramp.hdr").string());
  EXPECT_LT(j.at("median_rel_error").get<double>(), 0.05);
  EXPECT_GT(j.at("measurable_fraction").get<double>(), 0.9);
  EXPECT_LE(j.at("settle_cycles").get<int>(), 8);
  EXPECT_TRUE(j.contains("p95_rel_error"));
}

}  // namespace
}  // namespace probeless
