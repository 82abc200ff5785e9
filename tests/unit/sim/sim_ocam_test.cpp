// The sim's fisheye through an OCamCalib file (sim:fisheye_ocam=FILE), and the same lens as a
// fitted Kannala-Brandt model (fisheye_ocam_model=kannala_brandt): docs/sim.md.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "drivers/sim/sim_rig.hpp"
#include "support/test_data.hpp"

namespace probeless::sim {
namespace {

TEST(SimOCam, RendersThroughTheFileAndItsKannalaBrandtFit) {
  PROBELESS_REQUIRE_DATA("fisheye/ocamcalib/calib_results_fisheye.txt");
  const std::string file =
      (testing::shared_data_dir() / "fisheye/ocamcalib/calib_results_fisheye.txt").string();
  const Rig ocam = make_sim_rig(parse_sim_options("realtime=0,fisheye_ocam=" + file));
  const Rig kb = make_sim_rig(
      parse_sim_options("realtime=0,fisheye_ocam=" + file + ",fisheye_ocam_model=kannala_brandt"));
  EXPECT_EQ(ocam.calibration.fisheye->kind(), "ocam");
  EXPECT_EQ(kb.calibration.fisheye->kind(), "kannala_brandt");
  EXPECT_EQ(ocam.calibration.fisheye->width(), 1024);
  EXPECT_EQ(ocam.calibration.fisheye->height(), 768);
  // The fit lands where the file does, over the directions the frame sees.
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  double sum2 = 0, worst = 0;
  int n = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d d(g(rng), g(rng), g(rng));
    const auto a = ocam.calibration.fisheye->project(d);
    if (!a || !ocam.calibration.fisheye->in_image(*a)) continue;
    const auto b = kb.calibration.fisheye->project(d);
    ASSERT_TRUE(b.has_value());
    const double e = (*a - *b).norm();
    sum2 += e * e;
    worst = std::max(worst, e);
    ++n;
  }
  ASSERT_GT(n, 1000);
  const double rms = std::sqrt(sum2 / n);
  std::cout << "Kannala-Brandt fit of the OCamCalib lens: " << rms << " px RMS, " << worst
            << " px at most over " << n << " directions\n";
  EXPECT_LT(rms, 0.1);
  EXPECT_THROW(parse_sim_options("fisheye_ocam_model=pinhole"), std::invalid_argument);
  EXPECT_THROW(make_sim_rig(parse_sim_options("fisheye_ocam=/nonexistent/calib.txt")),
               std::invalid_argument);
}

}  // namespace
}  // namespace probeless::sim
