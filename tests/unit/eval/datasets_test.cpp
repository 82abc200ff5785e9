// The evaluator's datasets: PFM, both Middlebury layouts, alphamatting, recorded sequences;
// malformed inputs give errors that name the file; one small scene end to end.
#include <gtest/gtest.h>

#include <fstream>

#include "drivers/io/pfm.hpp"
#include "drivers/io/png.hpp"
#include "lab/eval/alphamatting_dataset.hpp"
#include "lab/eval/frames_dataset.hpp"
#include "lab/eval/middlebury_dataset.hpp"
#include "lab/eval/occlusion_eval.hpp"
#include "support/test_data.hpp"

namespace probeless::eval {
namespace {
namespace fs = std::filesystem;

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// Expects an ImageFileError whose message names `file`.
template <typename F>
void expect_file_error(F&& f, const fs::path& file, const std::string& what = {}) {
  try {
    f();
    FAIL() << "no error for " << file;
  } catch (const ImageFileError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    if (!what.empty()) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  }
}

// A small scene: a near box (left) in front of a far wall, textured colour.
void write_scene_images(const fs::path& dir, int w, int h, ImageRGB8& colour, ImageF& disparity) {
  colour = ImageRGB8(w, h);
  disparity = ImageF(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool near = x < w / 2 && y > h / 4;
      colour.at(x, y, 0) = near ? 200 : 40;
      colour.at(x, y, 1) = static_cast<std::uint8_t>((x * 7 + y * 3) % 64 + 60);
      colour.at(x, y, 2) = near ? 40 : 190;
      disparity.at(x, y) = near ? 40.0F : 20.0F;
    }
  fs::create_directories(dir);
}

TEST(Pfm, RoundTripsAndFlipsRows) {
  const auto dir = testing::scratch_dir();
  ImageF img(3, 2);
  img.at(0, 0) = 1.5F;
  img.at(2, 1) = -7.25F;
  write_pfm(dir / "a.pfm", img);
  EXPECT_EQ(read_pfm(dir / "a.pfm"), img);
  // Bottom row first on disk: the first float stored is the last row's first pixel.
  std::ifstream in(dir / "a.pfm", std::ios::binary);
  std::string magic, dims, scale;
  std::getline(in, magic);
  std::getline(in, dims);
  std::getline(in, scale);
  float first = 0;
  in.read(reinterpret_cast<char*>(&first), 4);
  EXPECT_EQ(first, img.at(0, 1));
}

TEST(Pfm, MalformedFilesNameTheFile) {
  const auto dir = testing::scratch_dir();
  expect_file_error([&] { read_pfm(dir / "missing.pfm"); }, dir / "missing.pfm", "cannot open");
  write_text(dir / "magic.pfm", "P6\n2 2\n-1\n");
  expect_file_error([&] { read_pfm(dir / "magic.pfm"); }, dir / "magic.pfm", "not a PFM");
  write_text(dir / "header.pfm", "Pf\ntwo 2\n-1\n");
  expect_file_error([&] { read_pfm(dir / "header.pfm"); }, dir / "header.pfm", "bad PFM header");
  write_text(dir / "short.pfm", "Pf\n4 4\n-1.0\n" + std::string(20, '\0'));
  expect_file_error([&] { read_pfm(dir / "short.pfm"); }, dir / "short.pfm", "truncated");
  write_text(dir / "colour.pfm", "PF\n1 1\n-1.0\n" + std::string(12, '\0'));
  expect_file_error([&] { read_pfm(dir / "colour.pfm"); }, dir / "colour.pfm", "colour");
}

TEST(Middlebury, BothLayoutsGiveMetricDepth) {
  const auto root = testing::scratch_dir();
  ImageRGB8 colour;
  ImageF disp;
  // 2014: Z = baseline f / (d + doffs).
  write_scene_images(root / "2014q" / "Box", 48, 32, colour, disp);
  write_png(root / "2014q/Box/im0.png", colour);
  disp.at(0, 0) = std::numeric_limits<float>::infinity();
  write_pfm(root / "2014q/Box/disp0GT.pfm", disp);
  write_text(root / "2014q/Box/calib.txt",
             "cam0=[ 500 0 24 ; 0 500 16 ; 0 0 1 ]\n doffs= 10 \nbaseline= 100\n width= 48");
  // v2: disparity * scale in an 8-bit PNG; median depth 1.5 m.
  write_scene_images(root / "v2" / "box", 48, 32, colour, disp);
  write_png(root / "v2/box/imL.png", colour);
  ImageGray8 gt(48, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x) gt.at(x, y) = static_cast<std::uint8_t>(disp.at(x, y) * 4);
  gt.at(1, 1) = 0;
  write_png(root / "v2/box/groundtruth.png", gt);
  write_text(root / "v2/box/info.txt", "4\n");

  const auto scenes = find_middlebury_scenes(root);
  ASSERT_EQ(scenes.size(), 2U);
  const auto s14 = load_middlebury_scene(root / "2014q/Box");
  EXPECT_EQ(s14.depth_mm.at(0, 0), 0);      // inf: unknown
  EXPECT_EQ(s14.depth_mm.at(0, 31), 1000);  // 100 * 500 / (40 + 10)
  EXPECT_EQ(s14.depth_mm.at(47, 0), std::lround(100.0 * 500 / 30));
  EXPECT_DOUBLE_EQ(s14.focal_px, 500);
  const auto sv2 = load_middlebury_scene(root / "v2/box");
  EXPECT_EQ(sv2.depth_mm.at(1, 1), 0);
  // More than half the pixels are the far wall (d = 20), so it sits at the median, 1.5 m.
  EXPECT_EQ(sv2.depth_mm.at(47, 0), 1500);
  EXPECT_EQ(sv2.depth_mm.at(0, 31), 750);

  // Malformed: missing calib value, bad info.txt, missing file.
  write_text(root / "2014q/Box/calib.txt", "cam0=[ 500 0 24 ]\n");
  expect_file_error([&] { load_middlebury_scene(root / "2014q/Box"); },
                    root / "2014q/Box/calib.txt", "doffs");
  write_text(root / "v2/box/info.txt", "scale\n");
  expect_file_error([&] { load_middlebury_scene(root / "v2/box"); }, root / "v2/box/info.txt");
  fs::remove(root / "v2/box/imL.png");
  expect_file_error([&] { load_middlebury_scene(root / "v2/box"); }, root / "v2/box");
  expect_file_error([&] { find_middlebury_scenes(root / "nowhere"); }, root / "nowhere");
}

TEST(Middlebury, VirtualObjectsLieBetweenForegroundAndBackground) {
  StereoScene s{"box", ImageRGB8(64, 48), DepthImage(64, 48), 100.0};
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) s.depth_mm.at(x, y) = x < 32 ? 1000 : 2000;
  for (auto shape : {VirtualShape::Plane, VirtualShape::Sphere}) {
    const auto v = place_virtual_object(s, shape);
    int front = 0, behind = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x) {
        if (!(v.at(x, y) > 0)) continue;
        EXPECT_GT(v.at(x, y), 1040.0F);
        EXPECT_LT(v.at(x, y), 1960.0F);
        (s.depth_mm.at(x, y) < v.at(x, y) ? front : behind)++;
      }
    EXPECT_GT(front, 0);
    EXPECT_GT(behind, 0);
  }
}

TEST(AlphaMatting, TrimapBecomesCategoriesAndTruthIsVisibility) {
  ImageRGB8 colour(3, 1);
  ImageGray8 trimap(3, 1), alpha(3, 1);
  trimap.at(0, 0) = 255;
  trimap.at(1, 0) = 128;
  alpha.at(0, 0) = 255;
  alpha.at(1, 0) = 51;
  const auto f = matting_frame(colour, trimap, alpha);
  EXPECT_EQ(f.real_depth_mm.at(0, 0), 500);  // foreground: in front of the virtual object
  EXPECT_EQ(f.real_depth_mm.at(1, 0), 0);    // unknown: "process"
  EXPECT_EQ(f.real_depth_mm.at(2, 0), 2000);
  EXPECT_FLOAT_EQ(f.truth.at(1, 0), 0.8F);
  EXPECT_EQ(f.mask.at(1, 0), 255);
  EXPECT_EQ(f.mask.at(0, 0), 0);
  const auto root = testing::scratch_dir();
  expect_file_error([&] { alphamatting_cases(root); }, root / "input");
}

TEST(RecordedFrames, MissingFilesNameTheFile) {
  const auto root = testing::scratch_dir();
  write_png(root / "000000_color.png", ImageRGB8(4, 4));
  write_png(root / "000000_depth.png", DepthImage(4, 4));
  expect_file_error([&] { recorded_cases(root); }, root / "000000_virtual_depth.pfm");
  write_pfm(root / "000000_virtual_depth.pfm", ImageF(4, 4, 1000.0F));
  write_png(root / "000000_matte.png", ImageGray8(4, 3));
  expect_file_error([&] { recorded_cases(root); }, root / "000000_matte.png", "size");
  write_png(root / "000000_matte.png", ImageGray8(4, 4, 255));
  const auto cases = recorded_cases(root);
  ASSERT_EQ(cases.size(), 1U);
  EXPECT_EQ(cases[0].frames.size(), 1U);
  EXPECT_EQ(cases[0].frames[0].mask.at(0, 0), 255);
}

TEST(EvalOcclusion, SmallMiddleburyCropEndToEnd) {
  PROBELESS_REQUIRE_DATA("middlebury/v2/venus");
  EvalOptions opts;
  opts.frames = 2;
  opts.crop_width = 96;
  opts.crop_height = 64;
  opts.plots_dir = testing::scratch_dir() / "plots";
  const auto cases = load_cases(
      "middlebury:" + (testing::shared_data_dir() / "middlebury/v2/venus").string(), opts);
  ASSERT_EQ(cases.size(), 2U);
  ComputeContext ctx;
  const auto report = evaluate(ctx, cases, opts);
  ASSERT_EQ(report.scenes.size(), 2U);
  for (const auto& m : all_method_names()) {
    const auto& s = report.mean.at(m);
    EXPECT_GE(s.mse, 0.0) << m;
    EXPECT_LE(s.mse, 1.0) << m;
    ASSERT_TRUE(s.temporal_noise.has_value()) << m;
  }
  const auto j = report_json(report);
  EXPECT_TRUE(j["scenes"][0]["methods"]["cvf"].contains("temporal_noise"));
  EXPECT_TRUE(j["mean"].contains("meta_soft"));
  EXPECT_TRUE(fs::exists(opts.plots_dir / "mse.svg"));
  EXPECT_TRUE(fs::exists(opts.plots_dir / "v2_venus_plane_cvf.png"));
  EXPECT_NE(format_report(report).find("temporal noise"), std::string::npos);
}

TEST(EvalOcclusion, BadDatasetSpecs) {
  EvalOptions opts;
  EXPECT_THROW(load_cases("middlebury", opts), std::invalid_argument);
  EXPECT_THROW(load_cases("kitti:/tmp", opts), std::invalid_argument);
  EXPECT_THROW(load_cases("middlebury:/nonexistent/dir", opts), ImageFileError);
}

}  // namespace
}  // namespace probeless::eval
