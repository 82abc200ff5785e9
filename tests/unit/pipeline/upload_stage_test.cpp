// The upload stage (app/pipeline/frame_stages.hpp): with the colour camera's Brown distortion
// it hands the later stages the frame remapped to the renderer's pinhole (the same bytes as
// kernels/undistort's reference), without distortion the frame as it came; a source whose
// frames are not the calibration's size is an error naming both.
#include <gtest/gtest.h>

#include <random>

#include "app/pipeline/frame_stages.hpp"
#include "kernels/undistort/undistort_reference.hpp"
#include "support/cl_context.hpp"

namespace probeless {
namespace {

RgbdFrame random_frame(int w, int h) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> byte(0, 255), mm(400, 4000);
  RgbdFrame f;
  f.colour = ImageRGB8(w, h);
  f.depth = DepthImage(w, h);
  for (auto& v : f.colour.elements()) v = static_cast<std::uint8_t>(byte(rng));
  for (auto& v : f.depth.elements()) v = static_cast<std::uint16_t>(mm(rng));
  return f;
}

struct Layer {
  ImageRGBA8 colour;
  ImageF depth;
  VirtualLayer view() { return {LdrColour{&colour}, &depth, std::nullopt}; }
};

Layer empty_layer(int w, int h) {
  return {ImageRGBA8(w, h), ImageF(w, h)};
}

template <typename T, int C>
std::vector<T> host(const DeviceImage<T, C>& d) {
  const auto image = d.download(testing::cl_context().queue());
  return {image.elements().begin(), image.elements().end()};
}

template <typename T, int C>
std::vector<T> host(const Image<T, C>& image) {
  return {image.elements().begin(), image.elements().end()};
}

TEST(UploadStage, UndistortsToTheRenderersPinhole) {
  PinholeIntrinsics k;  // 640 x 480
  const PinholeCamera rgb(k, BrownDistortion{0.2, -0.05, 0.001, -0.001, 0.0});
  UploadStage stage(testing::cl_context(), rgb);
  EXPECT_TRUE(stage.undistorts());
  const RgbdFrame frame = random_frame(k.width, k.height);
  Layer layer = empty_layer(k.width, k.height);
  const DeviceFrame out = stage.process(frame, layer.view());
  const UndistortMap map = *build_undistort_map(rgb);
  const auto want_colour = host(undistort_colour_reference(frame.colour, map));
  const auto got_colour = host(*out.colour);
  int off = 0;
  for (std::size_t i = 0; i < want_colour.size(); ++i) off += got_colour[i] != want_colour[i];
  EXPECT_LE(off, static_cast<int>(want_colour.size() / 1000));  // float rounding at .5
  EXPECT_EQ(host(*out.real_depth), host(undistort_depth_reference(frame.depth, map)));
  EXPECT_NE(host(*out.real_depth), host(frame.depth));  // it did move pixels
}

TEST(UploadStage, WithoutDistortionTheFrameIsCopiedAsItIs) {
  PinholeIntrinsics k;
  UploadStage stage(testing::cl_context(), PinholeCamera(k));
  EXPECT_FALSE(stage.undistorts());
  const RgbdFrame frame = random_frame(k.width, k.height);
  Layer layer = empty_layer(k.width, k.height);
  const DeviceFrame out = stage.process(frame, layer.view());
  EXPECT_EQ(host(*out.colour), host(frame.colour));
  EXPECT_EQ(host(*out.real_depth), host(frame.depth));
}

// The sensor's beyond-range holes (core/beyond_range.hpp) reach the occlusion stages filled,
// exactly as the pass fills them, while the frame itself (which tracking reads) keeps its
// holes; with the rule off the depth goes up as it came.
TEST(UploadStage, BeyondRangeHolesAreFilledOnTheWayUpNotInTheFrame) {
  PinholeIntrinsics k;
  RgbdFrame frame = random_frame(k.width, k.height);
  for (int y = 100; y < 300; ++y)
    for (int x = 100; x < 400; ++x) frame.depth.at(x, y) = 0;
  for (int y = 90; y < 310; ++y)  // the hole's rim: a wall at 4.2 m
    for (int x = 90; x < 410; ++x)
      if (frame.depth.at(x, y) != 0) frame.depth.at(x, y) = 4200;
  const DepthImage as_recorded = frame.depth;
  Layer layer = empty_layer(k.width, k.height);

  UploadStage on(testing::cl_context(), PinholeCamera(k), BeyondRangeRule{});
  DepthImage want = frame.depth;
  BeyondRangeScratch scratch;
  ASSERT_GT(fill_beyond_range_holes(want, BeyondRangeRule{}, scratch), 0u);
  EXPECT_EQ(host(*on.process(frame, layer.view()).real_depth), host(want));
  EXPECT_EQ(host(frame.depth), host(as_recorded));

  BeyondRangeRule off;
  off.far_mm = 0;
  UploadStage plain(testing::cl_context(), PinholeCamera(k), off);
  EXPECT_EQ(host(*plain.process(frame, layer.view()).real_depth), host(as_recorded));
}

TEST(UploadStage, AFrameOfAnotherSizeThanTheCalibrationIsAnErrorNamingBoth) {
  UploadStage stage(testing::cl_context(), PinholeCamera(PinholeIntrinsics{}));
  const RgbdFrame frame = random_frame(320, 240);
  Layer layer = empty_layer(320, 240);
  try {
    stage.process(frame, layer.view());
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("320 x 240"), std::string::npos) << what;
    EXPECT_NE(what.find("640 x 480"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace probeless
