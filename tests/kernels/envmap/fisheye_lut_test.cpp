// The fisheye lookup table (kernels/envmap/fisheye_lut.hpp) lands where each core/camera model
// projects, so the envmap update samples the same pixels whatever model the rig has.
#include "kernels/envmap/fisheye_lut.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/ocam.hpp"
#include "core/camera/pinhole.hpp"
#include "kernels/envmap/envmap_update.hpp"
#include "kernels/envmap/envmap_update_reference.hpp"
#include "support/cl_context.hpp"
#include "tests/kernels/envmap/envmap_test_support.hpp"
#include "tests/support/test_data.hpp"

namespace probeless::envmap {
namespace {

struct LutError {
  double max_px = 0;
  int compared = 0, missed = 0;  // missed: the model sees it inside the frame, the table not
};

// Random directions whose whole bilinear footprint lies inside the frame: the table's pixel
// against the model's own projection.
LutError lut_error(const CameraModel& camera, const FisheyeLut& lut, int samples = 20000) {
  std::mt19937 rng(3);
  std::normal_distribution<float> g;
  LutError e;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector3f d(g(rng), g(rng), g(rng));
    const auto want = camera.project(d.cast<double>());
    if (!want || !(want->x() >= 1 && want->y() >= 1 && want->x() < camera.width() - 2 &&
                   want->y() < camera.height() - 2))
      continue;
    const auto got = lut_pixel_reference(lut, d);
    if (!got) {
      ++e.missed;
      continue;
    }
    e.max_px = std::max(e.max_px, (got->cast<double>() - *want).norm());
    ++e.compared;
  }
  std::cout << camera.kind() << ": " << e.compared << " directions, table off the model by "
            << e.max_px << " px at most\n";
  return e;
}

TEST(FisheyeLut, EquidistantIsExactToFloatRounding) {
  // The sim's fisheye: the table is linear in its index, so interpolation adds nothing.
  const auto camera = KannalaBrandtCamera::equidistant(1024, 190);
  const auto lut = build_fisheye_lut(camera);
  EXPECT_EQ(lut->image_width, 1024);
  EXPECT_LT(lut->size, 600);  // two-pixel cells over a 1024 px image circle
  const LutError e = lut_error(camera, *lut);
  EXPECT_GT(e.compared, 5000);
  EXPECT_EQ(e.missed, 0);
  EXPECT_LT(e.max_px, 2e-3);
}

TEST(FisheyeLut, KannalaBrandtWithDistortion) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 4; ++trial) {
    const auto camera = testing::random_camera(rng, 640);
    const LutError e = lut_error(camera, *build_fisheye_lut(camera));
    EXPECT_GT(e.compared, 3000);
    EXPECT_EQ(e.missed, 0);
    EXPECT_LT(e.max_px, 0.01) << trial;  // measured 0.0062 px at most
  }
}

TEST(FisheyeLut, Pinhole) {
  const PinholeCamera camera(PinholeIntrinsics{}, BrownDistortion{-0.2, 0.05, 0.001, -0.001, 0});
  const LutError e = lut_error(camera, *build_fisheye_lut(camera, 1.0F));
  EXPECT_GT(e.compared, 1000);
  EXPECT_EQ(e.missed, 0);
  EXPECT_LT(e.max_px, 0.01);
}

TEST(FisheyeLut, OCamCalibFile) {
  PROBELESS_REQUIRE_DATA("fisheye/ocamcalib/calib_results_fisheye.txt");
  const auto path =
      ::probeless::testing::shared_data_dir() / "fisheye/ocamcalib/calib_results_fisheye.txt";
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const OCamCamera camera = OCamCamera::parse(text.str(), path.string());
  const auto lut = build_fisheye_lut(camera);
  const LutError e = lut_error(camera, *lut);
  EXPECT_GT(e.compared, 3000);
  EXPECT_EQ(e.missed, 0);
  EXPECT_LT(e.max_px, 0.01);
}

TEST(FisheyeLut, RejectsBadCells) {
  const auto camera = KannalaBrandtCamera::equidistant(64, 190);
  EXPECT_THROW(build_fisheye_lut(camera, 0.0F), std::invalid_argument);
  EXPECT_THROW(build_fisheye_lut(camera, 100.0F), std::invalid_argument);
}

// A fisheye source at another size than its calibration: sampled at the wrong pixels without
// any sign, so the update refuses it, naming both sizes and the model.
TEST(FisheyeLut, AFrameOfAnotherSizeIsAnErrorNamingBoth) {
  auto& ctx = ::probeless::testing::cl_context();
  EnvmapUpdate stage(ctx);
  const FisheyeView view = testing::view_of(KannalaBrandtCamera::equidistant(128, 190),
                                            testing::upward_R_camera_world());
  const DeviceImage<float, 4> frame(ctx, ImageRGBAF(160, 120));
  DeviceImage<float, 4> texels(ctx, make_texels(8)), pending(ctx, make_texels(8));
  try {
    stage.update(frame, view, false, texels, pending);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("160 x 120"), std::string::npos) << what;
    EXPECT_NE(what.find("kannala_brandt) is 128 x 128"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace probeless::envmap
