// The renderer draws and reads back only the objects' projected bounds (screen_bounds.hpp):
// the bounds hold every pixel the box can reach, and the pictures are the whole-frame ones,
// bit for bit, frame after frame, as objects move, leave the view or cross the near plane.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "app/render/renderer.hpp"
#include "app/render/screen_bounds.hpp"

namespace probeless::render {
namespace {

PinholeIntrinsics vga() {
  PinholeIntrinsics k;
  k.fx = 525.0;
  k.fy = 530.0;
  return k;
}

Eigen::Matrix4d pose_matrix(const Eigen::Vector3d& axis_angle, const Eigen::Vector3d& t,
                            double scale) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  const double angle = axis_angle.norm();
  if (angle > 0)
    m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle, axis_angle / angle).toRotationMatrix();
  m.topLeftCorner<3, 3>() *= scale;
  m.topRightCorner<3, 1>() = t;
  return m;
}

TEST(ScreenBounds, HoldEveryPixelThatAPointOfTheBoxInFrontOfTheNearPlaneReaches) {
  const PinholeIntrinsics k = vga();
  const double near_m = 0.05;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int straddling = 0, partial = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Eigen::Matrix4d m =
        pose_matrix({u(rng) * 2, u(rng) * 2, u(rng) * 2},
                    {u(rng) * 0.6, u(rng) * 0.5, 0.3 + u(rng) * 0.6}, 0.5 + 0.5 * (u(rng) + 1));
    const Eigen::Vector3f lo(-0.2f, -0.1f, -0.15f), hi(0.1f, 0.2f, 0.05f);
    const PixelRect r = projected_box(k, m, lo, hi, near_m);
    bool behind = false, ahead = false;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector4d p(lo.x() + (hi.x() - lo.x()) * 0.5 * (u(rng) + 1),
                              lo.y() + (hi.y() - lo.y()) * 0.5 * (u(rng) + 1),
                              lo.z() + (hi.z() - lo.z()) * 0.5 * (u(rng) + 1), 1.0);
      const Eigen::Vector3d c = (m * p).head<3>();
      if (c.z() < near_m) {
        behind = true;
        continue;
      }
      ahead = true;
      const double px = k.fx * c.x() / c.z() + k.cx, py = k.fy * c.y() / c.z() + k.cy;
      // The pixel whose centre is nearest the point, if it is on the image.
      const int x = static_cast<int>(std::lround(px)), y = static_cast<int>(std::lround(py));
      if (x < 0 || y < 0 || x >= k.width || y >= k.height) continue;
      ASSERT_TRUE(x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1)
          << "trial " << trial << ": (" << x << ", " << y << ") outside [" << r.x0 << ", " << r.x1
          << ") x [" << r.y0 << ", " << r.y1 << ")";
    }
    straddling += behind && ahead;
    partial += !r.empty() && r != PixelRect::whole(k.width, k.height);
  }
  EXPECT_GT(straddling, 10) << "boxes crossing the near plane were tried";
  EXPECT_GT(partial, 100) << "the bounds are smaller than the image for most boxes";
}

TEST(ScreenBounds, EmptyBehindTheCameraAndOffTheImage) {
  const PinholeIntrinsics k = vga();
  const Eigen::Vector3f lo(-0.1f, -0.1f, -0.1f), hi(0.1f, 0.1f, 0.1f);
  EXPECT_TRUE(
      projected_box(k, pose_matrix(Eigen::Vector3d::Zero(), {0, 0, -1}, 1), lo, hi, 0.05).empty());
  EXPECT_TRUE(
      projected_box(k, pose_matrix(Eigen::Vector3d::Zero(), {5, 0, 1}, 1), lo, hi, 0.05).empty());
  const PixelRect centred =
      projected_box(k, pose_matrix(Eigen::Vector3d::Zero(), {0, 0, 1}, 1), lo, hi, 0.05);
  // Corners at z = 0.9 project to 319.5 +- 525 * 0.1 / 0.9 = 261.2 .. 377.8.
  EXPECT_EQ(centred.x0, 260);
  EXPECT_EQ(centred.x1, 379);
  // Far off to one side but crossing the near plane: clamped, never wrapped.
  // The crossing at z = near reaches u = 319.5 + 525 * 0.15 / 0.05 = 1894.5 and, on the other
  // side, 319.5 - 525 * 0.05 / 0.05 = -205.5.
  const PixelRect wide =
      projected_box(k, pose_matrix(Eigen::Vector3d::Zero(), {0.05, 0, 0.05}, 1), lo, hi, 0.05);
  EXPECT_EQ(wide.x0, 0);
  EXPECT_EQ(wide.x1, k.width);
}

// Two renderers, one with the scissor and one without, along a path where objects come and
// go, one crosses the near plane, and the target switches between the two colour outputs.
TEST(RendererScissor, SamePicturesAsTheWholeFrameAlongAPath) {
  std::unique_ptr<Renderer> cut, whole;
  try {
    cut = std::make_unique<Renderer>();
    RendererConfig config;
    config.scissor = false;
    whole = std::make_unique<Renderer>(config);
  } catch (const std::exception& e) {
    GTEST_SKIP() << "no headless EGL/GLES 3 context: " << e.what();
  }
  std::vector<VirtualObject> objects(3);
  objects[0].mesh = std::make_shared<const Mesh>(make_pawn(0.25f));
  objects[1].mesh = std::make_shared<const Mesh>(make_sphere(0.1f));
  objects[1].T_world_object.translation = {0.4, 0.1, 0.1};
  objects[2].mesh = std::make_shared<const Mesh>(make_box({2.f, 2.f, 0.02f}));
  objects[2].T_world_object.translation = {0, 0, -0.02};
  const PinholeIntrinsics k = vga();

  RenderTarget a, b;
  int partial = 0, empty = 0;
  for (int frame = 0; frame < 24; ++frame) {
    const double angle = 0.4 * frame;
    const double distance = frame == 9 ? 0.08 : 0.6 + 0.05 * (frame % 5);  // 9: inside the box
    Eigen::Vector3d eye(distance * std::cos(angle), distance * std::sin(angle), 0.35);
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
    if (frame % 7 == 3) target = eye + Eigen::Vector3d(eye.x(), eye.y(), 0.1);  // looking away
    const Camera camera{k, camera_look_at(eye, target)};
    a.output = b.output =
        frame >= 12 && frame < 18 ? ColourOutput::LinearFloat : ColourOutput::Display8;
    cut->render(camera, objects, a);
    whole->render(camera, objects, b);
    ASSERT_TRUE(std::ranges::equal(a.depth_mm.elements(), b.depth_mm.elements()))
        << "frame " << frame;
    if (a.output == ColourOutput::LinearFloat)
      ASSERT_TRUE(std::ranges::equal(a.radiance.elements(), b.radiance.elements()))
          << "frame " << frame;
    else
      ASSERT_TRUE(std::ranges::equal(a.colour.elements(), b.colour.elements()))
          << "frame " << frame;
    partial += !a.drawn.empty() && a.drawn != PixelRect::whole(k.width, k.height);
    empty += a.drawn.empty();
  }
  EXPECT_GT(partial, 5) << "the scissor cut most frames";
  EXPECT_GT(empty, 0) << "a frame looked away from every object";
}

}  // namespace
}  // namespace probeless::render
