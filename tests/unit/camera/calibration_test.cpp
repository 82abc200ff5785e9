// Rig calibration TOML: the documented schema, the round trip through to_toml, and errors that
// name the key and the line.
#include "core/calibration.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "core/camera/kannala_brandt.hpp"
#include "core/camera/ocam.hpp"
#include "core/error.hpp"

namespace probeless {
namespace {

// The example of docs/camera-models.md.
constexpr const char* kExample = R"(# Asus Xtion colour camera and an upward 190 deg fisheye
[rgb]
width = 640
height = 480
fx = 525.0
fy = 525.0
cx = 319.5
cy = 239.5

[rgb.distortion]
k1 = 0.2624
k2 = -0.9531
p1 = -0.0054
p2 = 0.0026
k3 = 1.1633

[fisheye]
model = "kannala_brandt"
width = 1024
height = 1024
fx = 308.8
fy = 308.8
cx = 511.5
cy = 511.5
k = [0.0312, -0.0147, 0.0052, -0.0011]
max_theta = 1.658

[extrinsics]
T_rig_rgb = {translation = [0.0, 0.0, 0.0], rotation_xyzw = [0.0, 0.0, 0.0, 1.0]}
T_rig_fisheye = {translation = [0.0, -0.05, 0.02], rotation_xyzw = [-0.7071067811865476, 0.0, 0.0, 0.7071067811865476]}
depth_baseline_m = 0.075
)";

void expect_same(const RigCalibration& a, const RigCalibration& b) {
  EXPECT_EQ(a.rgb.intrinsics(), b.rgb.intrinsics());
  EXPECT_EQ(a.rgb.distortion(), b.rgb.distortion());
  EXPECT_EQ(a.fisheye_file, b.fisheye_file);
  ASSERT_EQ(a.fisheye == nullptr, b.fisheye == nullptr);
  if (a.fisheye) {
    EXPECT_EQ(a.fisheye->kind(), b.fisheye->kind());
    if (auto* kb = dynamic_cast<const KannalaBrandtCamera*>(a.fisheye.get())) {
      EXPECT_EQ(kb->params(), dynamic_cast<const KannalaBrandtCamera&>(*b.fisheye).params());
    }
    if (auto* oc = dynamic_cast<const OCamCamera*>(a.fisheye.get())) {
      EXPECT_EQ(oc->params(), dynamic_cast<const OCamCamera&>(*b.fisheye).params());
    }
  }
  for (auto [pa, pb] :
       {std::pair{&a.T_rig_rgb, &b.T_rig_rgb}, std::pair{&a.T_rig_fisheye, &b.T_rig_fisheye}}) {
    EXPECT_EQ(pa->translation, pb->translation);
    EXPECT_EQ(pa->rotation.coeffs(), pb->rotation.coeffs());
  }
  EXPECT_EQ(a.depth_baseline_m, b.depth_baseline_m);
}

TEST(RigCalibration, ParsesTheDocumentedExample) {
  const RigCalibration c = parse_rig_calibration(kExample);
  EXPECT_EQ(c.rgb.intrinsics(), (PinholeIntrinsics{640, 480, 525, 525, 319.5, 239.5}));
  EXPECT_EQ(c.rgb.distortion(), (BrownDistortion{0.2624, -0.9531, -0.0054, 0.0026, 1.1633}));
  ASSERT_TRUE(c.fisheye);
  const auto& kb = dynamic_cast<const KannalaBrandtCamera&>(*c.fisheye);
  EXPECT_EQ(kb.params().k, (std::array<double, 4>{0.0312, -0.0147, 0.0052, -0.0011}));
  EXPECT_EQ(kb.params().max_theta, 1.658);
  EXPECT_TRUE(c.fisheye_file.empty());
  // A -90 deg turn about x maps the fisheye's optical axis (camera +z) to the rig's +y.
  EXPECT_LT((c.T_rig_fisheye.rotation * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitY()).norm(),
            1e-12);
  EXPECT_EQ(c.T_rig_fisheye.translation, Eigen::Vector3d(0, -0.05, 0.02));
  EXPECT_EQ(c.depth_baseline_m, 0.075);
}

TEST(RigCalibration, RoundTripsThroughToToml) {
  const RigCalibration c = parse_rig_calibration(kExample);
  const RigCalibration back = parse_rig_calibration(to_toml(c), "written");
  expect_same(c, back);

  // Awkward values: full-precision doubles, integers-as-floats, no distortion, an OCam model.
  RigCalibration d;
  d.rgb = PinholeCamera({1280, 720, 1000.0 / 3, 2e3, 0.1 + 0.2, 359.5});
  OCamParams p;
  p.pol = {-551.7655, 0, 8.372454e-4, -6.474789e-7, 1.235631e-9};
  p.invpol = {730.949123,  315.876984,  -177.960849, -352.468231,
              -678.144608, -615.917273, -262.086205, -42.961956};
  p.xc = 381.777786;
  p.yc = 505.480427;
  p.width = 1024;
  p.height = 768;
  d.fisheye = std::make_shared<OCamCamera>(p);
  d.T_rig_rgb.translation = {1e-17, -3.25, 1.0 / 7};
  d.T_rig_fisheye.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  d.depth_baseline_m = 0.0581;
  const std::string text = to_toml(d);
  expect_same(d, parse_rig_calibration(text, "written"));
  EXPECT_EQ(text.find("[rgb.distortion]"), std::string::npos) << text;

  // A fisheye named by file is kept as a file, not loaded.
  RigCalibration f = d;
  f.fisheye = nullptr;
  f.fisheye_file = "fisheye \"cam\"/calib_results.txt";
  const RigCalibration fb = parse_rig_calibration(to_toml(f));
  EXPECT_EQ(fb.fisheye, nullptr);
  EXPECT_EQ(fb.fisheye_file, f.fisheye_file);

  // An RGB-D-only rig (a TUM sequence) has no [fisheye] table and reads back without one.
  RigCalibration none = d;
  none.fisheye = nullptr;
  const std::string none_text = to_toml(none);
  EXPECT_EQ(none_text.find("[fisheye]"), std::string::npos) << none_text;
  const RigCalibration none_back = parse_rig_calibration(none_text, "written");
  expect_same(none, none_back);
  EXPECT_EQ(none_back.fisheye, nullptr);
  EXPECT_TRUE(none_back.fisheye_file.empty());
}

TEST(RigCalibration, InlineOcamAndDefaults) {
  const RigCalibration c = parse_rig_calibration(R"(
[rgb]
width = 640
height = 480
fx = 500
fy = 500
cx = 320
cy = 240
[fisheye]
model = "ocam"
width = 640
height = 480
pol = [-200, 0, 0.0015]
invpol = [365, 200]
xc = 240
yc = 320
[extrinsics]
T_rig_rgb = {translation = [0, 0, 0], rotation_xyzw = [0, 0, 0, 1]}
T_rig_fisheye = {translation = [0, 0, 0], rotation_xyzw = [0, 0, 0, 1]}
)");
  EXPECT_TRUE(c.rgb.distortion().is_zero());
  const auto& oc = dynamic_cast<const OCamCamera&>(*c.fisheye);
  EXPECT_EQ(oc.params().c, 1.0);
  EXPECT_EQ(oc.params().d, 0.0);
  EXPECT_EQ(c.depth_baseline_m, 0.075);
}

struct BadCase {
  const char* name;
  std::string from, to;  // a replacement applied to kExample
  int line;
  const char* message;  // a piece of the error text
};

class RigCalibrationErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(RigCalibrationErrors, NameTheKeyAndLine) {
  const BadCase& bad = GetParam();
  std::string text = kExample;
  const auto at = text.find(bad.from);
  ASSERT_NE(at, std::string::npos) << bad.from;
  text.replace(at, bad.from.size(), bad.to);
  try {
    parse_rig_calibration(text, "rig.toml");
    FAIL() << "no ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.source(), "rig.toml");
    EXPECT_EQ(e.line(), bad.line) << e.what();
    EXPECT_NE(std::string(e.what()).find(bad.message), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, RigCalibrationErrors,
    ::testing::Values(
        BadCase{"MissingFx", "fx = 525.0\n", "", 2, "missing key 'fx' in [rgb]"},
        BadCase{"NotANumber", "cy = 239.5", "cy = \"middle\"", 8, "cy: expected a number"},
        BadCase{"FloatWidth", "width = 640\n", "width = 640.5\n", 3, "width: expected a positive"},
        BadCase{"UnknownKey", "k3 = 1.1633", "k4 = 1.1633", 15, "unknown key 'k4'"},
        // Sizes are bounded (core/read_limits.hpp): what is sized from them cannot be absurd.
        BadCase{"HugeWidth", "width = 640\n", "width = 1048576\n", 3,
                "width: expected a positive integer up to 32768"},
        BadCase{"TooManyPixels", "width = 1024\nheight = 1024", "width = 32768\nheight = 32768", 20,
                "32768x32768 is over the limit of 67108864 pixels"},
        BadCase{"BadModel", "\"kannala_brandt\"", "\"mei\"", 18, "model: expected"},
        BadCase{"ShortK", "k = [0.0312, -0.0147, 0.0052, -0.0011]", "k = [0.0312]", 25,
                "k: expected an array of 4"},
        BadCase{"MissingPose",
                "T_rig_rgb = {translation = [0.0, 0.0, 0.0], rotation_xyzw = "
                "[0.0, 0.0, 0.0, 1.0]}\n",
                "", 28, "missing key 'T_rig_rgb' in [extrinsics]"},
        BadCase{"MissingRotation", ", rotation_xyzw = [0.0, 0.0, 0.0, 1.0]}", "}", 29,
                "missing key 'rotation_xyzw'"},
        BadCase{"NotUnit", "[0.0, 0.0, 0.0, 1.0]", "[0.0, 0.0, 0.0, 2.0]", 29, "unit quaternion"},
        BadCase{"TomlSyntax", "fy = 525.0", "fy = = 525.0", 6, ""},
        BadCase{"MisspeltTable", "[fisheye]", "[fishy]", 17, "unknown key 'fishy'"},
        BadCase{"NegativeBaseline", "depth_baseline_m = 0.075", "depth_baseline_m = -1", 31,
                "depth_baseline_m must be positive"},
        BadCase{"FisheyeWithoutModel", "model = \"kannala_brandt\"\n", "", 17,
                "missing key 'model' in [fisheye]"},
        BadCase{"FileAndParams", "model = \"kannala_brandt\"",
                "model = \"ocam\"\nfile = \"calib.txt\"", 24,
                "unknown key 'cx' in [fisheye] (ocam) with a file"}),
    [](const ::testing::TestParamInfo<BadCase>& c) { return std::string(c.param.name); });

}  // namespace
}  // namespace probeless
