// The colour camera's undistortion (kernels/undistort): the device remap equals its CPU
// reference on random frames and distortions, the map puts a distorted point back where the
// pinhole draws it, depth stays a value of the frame, and no distortion means no map.
#include "kernels/undistort/undistort.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "kernels/undistort/undistort_reference.hpp"
#include "support/cl_context.hpp"

namespace probeless {
namespace {

using testing::cl_context;

PinholeCamera random_camera(std::mt19937& rng, int w, int h) {
  std::uniform_real_distribution<double> u(-1, 1);
  PinholeIntrinsics k;
  k.width = w;
  k.height = h;
  k.fx = 0.8 * w * (1 + 0.1 * u(rng));
  k.fy = k.fx * (1 + 0.02 * u(rng));
  k.cx = 0.5 * (w - 1) + 3 * u(rng);
  k.cy = 0.5 * (h - 1) + 3 * u(rng);
  // Colour cameras of RGB-D sensors: |k1| up to ~0.25 (Kinect v1 0.26, RealSense ~0.1).
  const BrownDistortion d{0.25 * u(rng), 0.1 * u(rng), 0.002 * u(rng), 0.002 * u(rng),
                          0.02 * u(rng)};
  return PinholeCamera(k, d);
}

TEST(Undistort, NoDistortionNoMap) {
  EXPECT_FALSE(build_undistort_map(PinholeCamera(PinholeIntrinsics{})).has_value());
}

TEST(Undistort, DeviceMatchesTheReferenceOnRandomFramesAndSizes) {
  std::mt19937 rng(4);
  auto& ctx = cl_context();
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{17, 9}, {160, 120}, {641, 479}}) {
    const PinholeCamera camera = random_camera(rng, w, h);
    const auto map = build_undistort_map(camera);
    ASSERT_TRUE(map.has_value());
    ImageRGB8 colour(w, h);
    DepthImage depth(w, h);
    std::uniform_int_distribution<int> byte(0, 255), mm(0, 8000);
    for (auto& v : colour.elements()) v = static_cast<std::uint8_t>(byte(rng));
    for (auto& v : depth.elements()) v = static_cast<std::uint16_t>(mm(rng));
    Undistort stage(ctx, *map);
    const DeviceImageRGB8 colour_in(ctx, colour);
    const DeviceDepthImage depth_in(ctx, depth);
    DeviceImageRGB8 colour_out;
    DeviceDepthImage depth_out;
    stage.colour(colour_in, colour_out);
    stage.depth(depth_in, depth_out);
    const ImageRGB8 got_colour = colour_out.download(ctx.queue());
    const DepthImage got_depth = depth_out.download(ctx.queue());
    const ImageRGB8 want_colour = undistort_colour_reference(colour, *map);
    const DepthImage want_depth = undistort_depth_reference(depth, *map);
    int off = 0;
    for (std::size_t i = 0; i < want_colour.elements().size(); ++i)
      off += std::abs(got_colour.elements()[i] - want_colour.elements()[i]) > 0 ? 1 : 0;
    EXPECT_LE(off, static_cast<int>(want_colour.elements().size() / 1000)) << w << "x" << h;
    const auto as_vector = [](const DepthImage& d) {
      return std::vector<std::uint16_t>(d.elements().begin(), d.elements().end());
    };
    EXPECT_EQ(as_vector(got_depth), as_vector(want_depth)) << w << "x" << h;
    // Nearest, never blended: every depth is one of the frame's (or 0 outside it).
    const std::set<std::uint16_t> values(depth.elements().begin(), depth.elements().end());
    for (const auto v : got_depth.elements()) EXPECT_TRUE(v == 0 || values.count(v));
  }
}

// A point the distorted camera sees lands, after the remap, where the ideal pinhole (what
// the renderer draws with) projects it: sample a ramp image and read the position back.
TEST(Undistort, PutsPointsWhereThePinholeDrawsThem) {
  std::mt19937 rng(8);
  const int w = 320, h = 240;
  const PinholeCamera camera = random_camera(rng, w, h);
  const auto map = build_undistort_map(camera);
  ASSERT_TRUE(map.has_value());
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  const PinholeCamera ideal(camera.intrinsics());
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), 1.0);
    const auto seen = camera.project(p), drawn = ideal.project(p);
    ASSERT_TRUE(seen && drawn);
    const int x = static_cast<int>(std::lround(drawn->x())),
              y = static_cast<int>(std::lround(drawn->y()));
    if (x < 0 || y < 0 || x >= w || y >= h) continue;
    // The map at the nearest output pixel points at the distorted pixel within the map's
    // slope times half a pixel.
    const Eigen::Vector2d at(map->source.at(x, y, 0), map->source.at(x, y, 1));
    EXPECT_LT((at - *seen).norm(), 1.0) << i;
  }
}

TEST(Undistort, RejectsAFrameOfAnotherSize) {
  std::mt19937 rng(2);
  auto& ctx = cl_context();
  const auto map = build_undistort_map(random_camera(rng, 64, 48));
  Undistort stage(ctx, *map);
  const DeviceImageRGB8 wrong(ctx, ImageRGB8(48, 64));
  DeviceImageRGB8 out;
  try {
    stage.colour(wrong, out);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("48 x 64"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("64 x 48"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace probeless
