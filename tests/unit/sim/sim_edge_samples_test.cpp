// The sim's mixed pixels at silhouettes (edge_samples > 1, SimRenderer::set_edge_samples): the
// pixels a silhouette crosses hold both surfaces in proportion, and the truth lists their two
// layers; off (the default) the frames are the ones every other test was taken with.
#include <gtest/gtest.h>

#include <cmath>

#include "drivers/sim/sim_rig.hpp"
#include "tests/unit/sim/sim_first_frame.hpp"

namespace probeless::sim {
namespace {

// t = 1.5 s on the tabletop: the near hand and the arm over the table, the camera moving.
const std::string kSpec = "realtime=0,trajectory=tabletop,near_occluder=1,start=1.5,frames=1";

double linear(std::uint8_t v) {
  return std::pow(v / 255.0, 2.2);
}  // the sim's gamma

TEST(SimEdgeSamples, OptionParsesAndBadValuesAreClearErrors) {
  EXPECT_EQ(parse_sim_options("").edge_samples, 1);
  EXPECT_EQ(parse_sim_options("edge_samples=4").edge_samples, 4);
  for (const char* bad : {"edge_samples=0", "edge_samples=9", "edge_samples=two"}) {
    try {
      parse_sim_options(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'edge_samples'"), std::string::npos) << e.what();
    }
  }
}

TEST(SimEdgeSamples, SilhouettePixelsMixTheirTwoLayersAndNothingElseChanges) {
  const RgbdFrame hard = first_frame(kSpec), soft = first_frame(kSpec + ",edge_samples=4");
  ASSERT_TRUE(hard.truth && soft.truth);
  EXPECT_TRUE(hard.truth->mixed_pixels.empty()) << "off by default";
  const auto& mixed = soft.truth->mixed_pixels;
  ASSERT_GT(mixed.size(), 1000u) << "the hand's and the arm's outlines, the table's edge";

  const int w = soft.colour.width();
  std::vector<std::uint8_t> listed(soft.colour.pixel_count(), 0);
  double err = 0;
  std::uint32_t last = 0;
  int fractional_occluder = 0;
  for (const MixedPixel& m : mixed) {
    ASSERT_LT(m.index, soft.colour.pixel_count());
    EXPECT_TRUE(&m == mixed.data() || m.index > last) << "in index order, once each";
    last = m.index;
    listed[m.index] = 1;
    ASSERT_GT(m.near_coverage, 0.0F);
    ASSERT_LT(m.near_coverage, 1.0F);
    ASSERT_LT(m.near_mm, m.far_mm);
    // The observed colour is the layers' mix in linear light (the sensor noise aside).
    for (int c = 0; c < 3; ++c) {
      const double want = m.near_coverage * linear(m.near_rgb[static_cast<std::size_t>(c)]) +
                          (1 - m.near_coverage) * linear(m.far_rgb[static_cast<std::size_t>(c)]);
      err +=
          std::fabs(linear(soft.colour.data()[3 * m.index + static_cast<std::size_t>(c)]) - want);
    }
    // Depth and truth stay the centre ray's: the same as without edge samples.
    const int x = static_cast<int>(m.index) % w, y = static_cast<int>(m.index) / w;
    ASSERT_EQ(soft.truth->clean_depth.at(x, y), hard.truth->clean_depth.at(x, y));
    fractional_occluder += soft.truth->occluder_mask.at(x, y) != 0;
  }
  EXPECT_LT(err / (3.0 * static_cast<double>(mixed.size())), 0.01) << "mean linear error";
  EXPECT_GT(fractional_occluder, 200) << "the occluders' own outlines are mixed";

  // Away from the silhouettes the frame is the one-ray frame, bit for bit (the same noise).
  int changed_elsewhere = 0;
  for (int y = 1; y + 1 < soft.colour.height(); ++y)
    for (int x = 1; x + 1 < w; ++x) {
      bool near_edge = false;
      for (int v = -1; v <= 1; ++v)
        for (int u = -1; u <= 1; ++u)
          near_edge = near_edge || listed[static_cast<std::size_t>((y + v) * w + x + u)];
      if (near_edge) continue;
      for (int c = 0; c < 3; ++c)
        changed_elsewhere += soft.colour.at(x, y, c) != hard.colour.at(x, y, c);
    }
  // Pixels next to a jump whose own footprint holds one surface are averaged too (texture
  // anti-aliasing): a few, never the bulk of the frame.
  EXPECT_LT(changed_elsewhere, 2000);
}

TEST(SimEdgeSamples, TheSameFrameForAnyThreadCount) {
  const RgbdFrame one = first_frame(kSpec + ",edge_samples=3,threads=1"),
                  three = first_frame(kSpec + ",edge_samples=3,threads=3");
  ASSERT_EQ(one.colour.pixel_count(), three.colour.pixel_count());
  EXPECT_TRUE(std::equal(one.colour.data(), one.colour.data() + 3 * one.colour.pixel_count(),
                         three.colour.data()));
  ASSERT_EQ(one.truth->mixed_pixels.size(), three.truth->mixed_pixels.size());
  for (std::size_t i = 0; i < one.truth->mixed_pixels.size(); ++i) {
    EXPECT_EQ(one.truth->mixed_pixels[i].index, three.truth->mixed_pixels[i].index);
    EXPECT_EQ(one.truth->mixed_pixels[i].near_rgb, three.truth->mixed_pixels[i].near_rgb);
  }
}

}  // namespace
}  // namespace probeless::sim
