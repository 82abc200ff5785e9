#pragma once
// Frames with every field set (pixels, exposure, truth) for recording round trips, and
// helpers to compare what comes back.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/calibration.hpp"
#include "core/camera/kannala_brandt.hpp"
#include "core/frame.hpp"
#include "drivers/replay/recording_writer.hpp"

namespace probeless::testing {

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

inline RigCalibration test_calibration() {
  RigCalibration c;
  c.rgb = PinholeCamera(PinholeIntrinsics{32, 24, 30.1, 30.2, 15.5, 11.5},
                        BrownDistortion{0.01, -0.002, 0, 0, 0});
  c.T_rig_rgb.translation = {0.01, 0.02, 0.03};
  c.fisheye = std::make_shared<KannalaBrandtCamera>(KannalaBrandtCamera::equidistant(16, 190));
  return c;
}

template <typename ImageT>
ImageT noise_image(int w, int h, std::mt19937& rng, unsigned max_value) {
  ImageT image(w, h);
  std::uniform_int_distribution<unsigned> dist(0, max_value);
  for (auto& v : image.elements()) v = static_cast<typename ImageT::value_type>(dist(rng));
  return image;
}

struct TestFrames {
  std::vector<RgbdFrame> rgbd;
  std::vector<FisheyeFrame> fisheye;
};

// `n` frames per stream at 20 ms (RGB-D) and 15 ms (fisheye, offset by 3 ms). Truth on all
// RGB-D frames, on every other fisheye frame; one light shared by frames 0..2 and another after.
inline TestFrames make_test_frames(int n, bool truth = true, unsigned seed = 7) {
  std::mt19937 rng(seed);
  TestFrames out;
  auto light_a = std::make_shared<Cubemap>(2);
  auto light_b = std::make_shared<Cubemap>(3);
  std::uniform_real_distribution<float> radiance(0.0f, 1e4f);
  for (auto* cube : {light_a.get(), light_b.get()})
    for (auto& face : cube->faces)
      for (auto& v : face.elements()) v = radiance(rng);
  for (int i = 0; i < n; ++i) {
    RgbdFrame f;
    f.sequence = 100 + static_cast<std::uint64_t>(i);
    f.timestamp_ns = 5'000'000'123 + i * 20'000'000LL;
    f.colour = noise_image<ImageRGB8>(32, 24, rng, 255);
    f.depth = noise_image<DepthImage>(32, 24, rng, 65535);
    if (truth) {
      auto t = std::make_shared<FrameTruth>();
      t->clean_depth = noise_image<DepthImage>(32, 24, rng, 4000);
      t->occluder_mask = noise_image<ImageGray8>(32, 24, rng, 1);
      for (auto& v : t->occluder_mask.elements()) v = v ? 255 : 0;
      Pose p;
      p.translation = {0.1 * i, -0.2 / (i + 3), 1.0 / 3.0};
      p.rotation = Eigen::Quaterniond(
          Eigen::AngleAxisd(0.1 * i + 0.01, Eigen::Vector3d(1, 2, 3).normalized()));
      t->rig_pose = p;
      t->light = i < 3 ? light_a : light_b;
      f.truth = t;
    }
    out.rgbd.push_back(std::move(f));

    FisheyeFrame g;
    g.sequence = static_cast<std::uint64_t>(i);
    g.timestamp_ns = 5'003'000'000 + i * 15'000'000LL;
    g.raw = noise_image<ImageRGB16>(16, 16, rng, 4095);
    g.bit_depth = 12;
    g.black_level = 64;
    g.exposure.exposure.time_s = 0.01 / (1 << (i % 3)) + 1e-7 / 3;
    g.exposure.exposure.gain_db = 0.1 * i - 1.0 / 7.0;
    const BracketLevel levels[4] = {BracketLevel::Low, BracketLevel::Medium, BracketLevel::High,
                                    BracketLevel::Medium};
    g.exposure.level = levels[i % 4];
    g.exposure.cycle_position = static_cast<std::uint32_t>(i % 4);
    g.exposure.cycle = static_cast<std::uint64_t>(i / 4);
    if (truth && i % 2 == 0) {
      auto t = std::make_shared<FrameTruth>();
      Pose p;
      p.translation = {0.0, 0.5 * i, 1e-9};
      t->rig_pose = p;
      t->light = light_a;
      g.truth = t;
    }
    out.fisheye.push_back(std::move(g));
  }
  return out;
}

inline void write_recording(const std::filesystem::path& dir, const TestFrames& frames,
                            replay::RecordingWriterOptions options = {}) {
  replay::RecordingWriter writer(dir, test_calibration(), options);
  for (const auto& f : frames.rgbd) writer.append(f);
  for (const auto& f : frames.fisheye) writer.append(f);
  writer.finish();
}

inline void expect_same_truth(const std::shared_ptr<const FrameTruth>& a,
                              const std::shared_ptr<const FrameTruth>& b) {
  ASSERT_EQ(a == nullptr, b == nullptr);
  if (!a) return;
  EXPECT_EQ(a->clean_depth, b->clean_depth);
  EXPECT_EQ(a->occluder_mask, b->occluder_mask);
  ASSERT_EQ(a->rig_pose.has_value(), b->rig_pose.has_value());
  if (a->rig_pose) {
    EXPECT_EQ(a->rig_pose->translation, b->rig_pose->translation);
    EXPECT_EQ(a->rig_pose->rotation.coeffs(), b->rig_pose->rotation.coeffs());
  }
  ASSERT_EQ(a->light == nullptr, b->light == nullptr);
  if (a->light) {
    EXPECT_TRUE(*a->light == *b->light);
  }
}

inline void expect_same(const RgbdFrame& a, const RgbdFrame& b) {
  EXPECT_EQ(a.sequence, b.sequence);
  EXPECT_EQ(a.timestamp_ns, b.timestamp_ns);
  EXPECT_EQ(a.colour, b.colour);
  EXPECT_EQ(a.depth, b.depth);
  expect_same_truth(a.truth, b.truth);
}

inline void expect_same(const FisheyeFrame& a, const FisheyeFrame& b) {
  EXPECT_EQ(a.sequence, b.sequence);
  EXPECT_EQ(a.timestamp_ns, b.timestamp_ns);
  EXPECT_EQ(a.raw, b.raw);
  EXPECT_EQ(a.bit_depth, b.bit_depth);
  EXPECT_EQ(a.black_level, b.black_level);
  EXPECT_EQ(a.exposure, b.exposure);
  expect_same_truth(a.truth, b.truth);
}

}  // namespace probeless::testing
