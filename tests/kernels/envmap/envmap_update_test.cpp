#include "kernels/envmap/envmap_update.hpp"

#include <gtest/gtest.h>

#include <random>

#include "envmap_test_support.hpp"
#include "kernels/envmap/envmap_update_reference.hpp"
#include "kernels/hdr/hdr_conversion.hpp"
#include "support/cl_context.hpp"

namespace probeless::envmap {
namespace {

using namespace envmap::testing;
using probeless::testing::cl_context;

using Device4 = DeviceImage<float, 4>;

struct Texels {
  ImageRGBAF texels, pending;
};

// One update on the device from host state.
Texels device_update(EnvmapUpdate& stage, const ImageRGBAF& image, const FisheyeView& view,
                     bool publish, const ImageRGBAF& texels, const ImageRGBAF& pending) {
  auto& ctx = cl_context();
  const Device4 im(ctx, image);
  Device4 t(ctx, texels), p(ctx, pending);
  stage.update(im, view, publish, t, p);
  return {t.download(ctx.queue()), p.download(ctx.queue())};
}

class EnvmapUpdateTest : public ::testing::TestWithParam<UpdateRule> {};

TEST_P(EnvmapUpdateTest, MatchesTheReferenceOnRandomPosesAndSizes) {
  std::mt19937 rng(7);
  UpdateParams params;
  params.rule = GetParam();
  EnvmapUpdate stage(cl_context(), params);
  const std::vector<std::pair<int, int>> sizes{{1, 33}, {3, 64}, {17, 101}, {32, 256}, {129, 512}};
  for (const auto& [n, image_size] : sizes) {
    for (int trial = 0; trial < 3; ++trial) {
      const FisheyeView view = random_view(rng, image_size, image_size + trial);
      const ImageRGBAF image = random_image(rng, image_size, image_size + trial);
      Texels want{random_texels(rng, n), random_texels(rng, n)};
      const bool publish = trial == 2;
      const Texels got = device_update(stage, image, view, publish, want.texels, want.pending);
      envmap_update_reference(image, view, params, publish, want.texels, want.pending);
      const int allowed = std::max(2, 6 * n * n / 500);
      EXPECT_LE(count_mismatches(got.texels, want.texels), allowed) << n << " " << trial;
      EXPECT_LE(count_mismatches(got.pending, want.pending), allowed) << n << " " << trial;
    }
  }
}

// With a room box: the texel directions are box-projected before the camera model.
TEST_P(EnvmapUpdateTest, ParallaxMatchesTheReference) {
  std::mt19937 rng(17);
  UpdateParams params;
  params.rule = GetParam();
  EnvmapUpdate stage(cl_context(), params);
  for (const auto& [n, image_size] : std::vector<std::pair<int, int>>{{5, 64}, {48, 384}}) {
    for (int trial = 0; trial < 3; ++trial) {
      FisheyeView view = random_view(rng, image_size);
      add_random_room(rng, view);
      const ImageRGBAF image = random_image(rng, image_size, image_size);
      Texels want{random_texels(rng, n), random_texels(rng, n)};
      const Texels got = device_update(stage, image, view, trial == 2, want.texels, want.pending);
      ImageRGBAF distant = want.texels, distant_pending = want.pending;
      envmap_update_reference(image, view, params, trial == 2, want.texels, want.pending);
      const int allowed = std::max(2, 6 * n * n / 500);
      EXPECT_LE(count_mismatches(got.texels, want.texels), allowed) << n << " " << trial;
      EXPECT_LE(count_mismatches(got.pending, want.pending), allowed) << n << " " << trial;
      // ... and the box made a difference.
      FisheyeView no_room = view;
      no_room.room.reset();
      envmap_update_reference(image, no_room, params, trial == 2, distant, distant_pending);
      const int differ =
          count_mismatches(distant, want.texels) + count_mismatches(distant_pending, want.pending);
      EXPECT_GT(differ, 6 * n * n / 10) << n << " " << trial;
    }
  }
}

// The Kalman kernels skip groups of texels the fisheye cannot see before computing anything
// (envmap_update.cl, group_hidden). From empty texels every texel the reference sees gets a
// weight: the device must give weight to the same texels, with and without parallax (the
// room widens the bound), on random fisheyes of random fields of view and orientations.
TEST(EnvmapUpdateCull, KalmanSkipsOnlyTexelsTheFisheyeCannotSee) {
  std::mt19937 rng(29);
  UpdateParams params;
  params.rule = UpdateRule::Kalman;
  EnvmapUpdate stage(cl_context(), params);
  const int n = 64, size = 256;
  for (int trial = 0; trial < 24; ++trial) {
    FisheyeView view = random_view(rng, size);
    if (trial % 2 == 1) add_random_room(rng, view);
    const ImageRGBAF image = random_image(rng, size, size);
    ImageRGBAF want = make_texels(n), want_pending = make_texels(n);
    const Texels got = device_update(stage, image, view, false, want, want_pending);
    envmap_update_reference(image, view, params, false, want, want_pending);
    int seen = 0, differ = 0;
    for (int y = 0; y < 6 * n; ++y)
      for (int x = 0; x < n; ++x) {
        const bool a = got.texels.at(x, y, 3) > 0.0F, b = want.at(x, y, 3) > 0.0F;
        seen += b;
        differ += a != b;
      }
    EXPECT_GT(seen, 6 * n * n / 20) << "trial " << trial << ": the fisheye sees too little";
    EXPECT_LT(seen, 6 * n * n) << "trial " << trial << ": nothing left to cull";
    EXPECT_LE(differ, 2) << "trial " << trial << " of " << seen << " seen texels";
  }
}

// The fused kernel converts the four raw pixels each texel reads as HdrConversion converts the
// whole frame: on the device, update_raw equals convert + update bit for bit (one program,
// contraction off), and the composed CPU references within float rounding.
TEST_P(EnvmapUpdateTest, RawUpdateEqualsConversionThenUpdate) {
  auto& ctx = cl_context();
  std::mt19937 rng(11);
  UpdateParams params;
  params.rule = GetParam();
  const std::vector<std::pair<int, int>> sizes{{1, 33}, {17, 101}, {32, 256}, {128, 1024}};
  int updated = 0, compared = 0;
  for (const auto& [n, image_size] : sizes) {
    for (int trial = 0; trial < 2; ++trial) {
      HdrConversionParams hdr;
      if (trial == 1) {  // the image circle crop, cutting through the frame
        hdr.circle_cx = 0.5F * static_cast<float>(image_size - 1) + 0.25F;
        hdr.circle_cy = 0.5F * static_cast<float>(image_size - 1);
        hdr.circle_radius = 0.45F * static_cast<float>(image_size);
      }
      EnvmapUpdate stage(ctx, params, hdr);
      HdrConversion conversion(ctx, hdr);
      FisheyeView view = random_view(rng, image_size, image_size + trial);
      if (trial == 1) add_random_room(rng, view);
      const ImageRGB16 raw = random_raw(rng, image_size, image_size + trial);
      const Exposure exposure{0.004 * (trial + 1), 3.0 * trial};
      const ImageRGBAF texels0 = random_texels(rng, n), pending0 = random_texels(rng, n);
      const bool publish = trial == 1;

      const DeviceImage<std::uint16_t, 3> raw_device(ctx, raw);
      Device4 t(ctx, texels0), p(ctx, pending0);
      stage.update_raw(raw_device, 12, 256, exposure, view, publish, t, p);
      const Texels fused{t.download(ctx.queue()), p.download(ctx.queue())};

      Device4 converted;
      conversion.convert(raw_device, 12, 256, exposure, converted);
      const Texels two_stage =
          device_update(stage, converted.download(ctx.queue()), view, publish, texels0, pending0);
      EXPECT_EQ(count_mismatches(fused.texels, two_stage.texels), 0) << n << " " << trial;
      EXPECT_EQ(count_mismatches(fused.pending, two_stage.pending), 0) << n << " " << trial;
      for (std::size_t i = 0; i < fused.texels.pixel_count(); ++i) {
        ASSERT_EQ(fused.texels.data()[4 * i], two_stage.texels.data()[4 * i]) << "not bit-equal";
        ASSERT_EQ(fused.pending.data()[4 * i + 3], two_stage.pending.data()[4 * i + 3]);
      }

      Texels want{texels0, pending0};
      envmap_update_raw_reference(raw, 12, 256, exposure, hdr, view, params, publish, want.texels,
                                  want.pending);
      const int allowed = std::max(2, 6 * n * n / 500);
      EXPECT_LE(count_mismatches(fused.texels, want.texels), allowed) << n << " " << trial;
      EXPECT_LE(count_mismatches(fused.pending, want.pending), allowed) << n << " " << trial;
      updated +=
          count_mismatches(fused.texels, texels0) + count_mismatches(fused.pending, pending0);
      compared += 6 * n * n;
    }
  }
  EXPECT_GT(updated, compared / 4);  // the frames did update a good part of the texels
}

INSTANTIATE_TEST_SUITE_P(Rules, EnvmapUpdateTest,
                         ::testing::Values(UpdateRule::Kalman, UpdateRule::BestScore),
                         [](const auto& param_info) {
                           return std::string(param_info.param == UpdateRule::Kalman ? "Kalman"
                                                                                     : "BestScore");
                         });

// The reference's projection (a polynomial arctangent and the fisheye table, as the kernel's)
// lands where core's KannalaBrandtCamera::project does: sampling a linear ramp image returns
// the pixel position.
TEST(EnvmapUpdateReference, ProjectsLikeTheCameraModel) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int trial = 0; trial < 5; ++trial) {
    const KannalaBrandtCamera camera = random_camera(rng, 300);
    const FisheyeView view = view_of(camera, random_rotation(rng));
    ImageRGBAF ramp(300, 300);
    for (int y = 0; y < 300; ++y)
      for (int x = 0; x < 300; ++x) {
        ramp.at(x, y, 0) = static_cast<float>(x);
        ramp.at(x, y, 1) = static_cast<float>(y);
        ramp.at(x, y, 3) = 1.0F;
      }
    int compared = 0;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3f d(u(rng), u(rng), u(rng));
      const auto s = sample_fisheye_reference(ramp, view, d);
      const auto px = camera.project(view.R_camera_world * d.cast<double>());
      if (!s) continue;
      ASSERT_TRUE(px.has_value());
      // The fisheye table's bilinear interpolation (fisheye_lut_test.cpp): under 0.01 px.
      EXPECT_NEAR((*s)[0], px->x(), 0.01);
      EXPECT_NEAR((*s)[1], px->y(), 0.01);
      ++compared;
    }
    EXPECT_GT(compared, 500);
  }
}

// --- Parallax: a room painted with a smooth function of the world point ---

// Positive, smooth, a few radians per metre: 0.35 m of parallax changes it by tens of percent.
float paint(const Eigen::Vector3f& p) {
  return std::exp(std::sin(2.0F * p.x()) + std::cos(3.0F * p.y()) + 0.5F * p.z());
}

TEST(EnvmapUpdateParallax, BoxExitIsOnTheWallAlongTheRay) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  const Eigen::Vector3f lo(-2.5F, -2.0F, 0.0F), hi(2.5F, 3.0F, 2.7F), k(0.3F, -0.4F, 1.1F);
  for (int i = 0; i < 1000; ++i) {
    Eigen::Vector3f d(u(rng), u(rng), u(rng));
    d[i % 3] = i % 2 ? 1.0F : -1.0F;  // a cube texel direction: one component +-1
    const float t = box_exit(lo - k, hi - k, d);
    ASSERT_GT(t, 0.0F);
    const Eigen::Vector3f p = k + t * d;
    // On the box's surface: inside every slab, on the boundary of one.
    const float outside = ((p - hi).cwiseMax(lo - p)).maxCoeff();
    EXPECT_NEAR(outside, 0.0F, 1e-5F);
  }
  // An axis the ray does not move along (0 / 0 and x / 0) is ignored.
  EXPECT_FLOAT_EQ(box_exit(lo - k, hi - k, Eigen::Vector3f(0, 0, 1)), 2.7F - 1.1F);
  EXPECT_FLOAT_EQ(
      box_exit(Eigen::Vector3f(0, -1, -1), Eigen::Vector3f(1, 1, 1), Eigen::Vector3f(0, 1, 0)),
      1.0F);
  // The direction from the fisheye hits the same wall point.
  FisheyeView view;
  view.room = RoomBox{lo.cast<double>(), hi.cast<double>()};
  view.keyframe_position = k.cast<double>();
  view.position = Eigen::Vector3d(0.6, 0.1, 1.2);
  const ParallaxConstants pc = parallax_constants(view);
  ASSERT_TRUE(pc.enabled);
  const Eigen::Vector3f d(0.2F, 1.0F, 0.4F);
  const Eigen::Vector3f w = parallax_direction(pc, d);
  const Eigen::Vector3f wall = k + box_exit(lo - k, hi - k, d) * d;
  EXPECT_LT((view.position.cast<float>() + w - wall).norm(), 1e-5F);
  // A keyframe outside the box keeps distant light.
  view.keyframe_position = Eigen::Vector3d(0, 0, 3.0);
  EXPECT_FALSE(parallax_constants(view).enabled);
}

TEST(EnvmapUpdateParallax, TexelsShowTheWallsFromTheKeyframesPosition) {
  const int size = 384, n = 32;
  const Eigen::Vector3f lo(-2.5F, -2.5F, 0.0F), hi(2.5F, 2.5F, 2.7F);
  const Eigen::Vector3f k(0.2F, -1.1F, 1.15F), c = k + Eigen::Vector3f(0.33F, 0.12F, 0.0F);
  const KannalaBrandtCamera camera = KannalaBrandtCamera::equidistant(size, 190);
  FisheyeView view = view_of(camera, upward_R_camera_world());
  view.room = RoomBox{lo.cast<double>(), hi.cast<double>()};
  view.keyframe_position = k.cast<double>();
  view.position = c.cast<double>();
  // The frame the fisheye at c takes of the painted room.
  ImageRGBAF image(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const auto ray = camera.unproject(Eigen::Vector2d(x, y));
      if (!ray) continue;  // outside the image circle: quality 0
      const Eigen::Vector3f d = (view.R_camera_world.transpose() * *ray).cast<float>();
      const Eigen::Vector3f p = c + box_exit(lo - c, hi - c, d) * d;
      for (int ch = 0; ch < 3; ++ch) image.at(x, y, ch) = paint(p);
      image.at(x, y, 3) = 0.5F;
    }
  const auto rms_error = [&](const FisheyeView& v) {
    UpdateParams params;
    EnvmapUpdate stage(cl_context(), params);
    const Texels r =
        device_update(stage, image, v, false, envmap::make_texels(n), envmap::make_texels(n));
    double err2 = 0;
    int seen = 0;
    for (int row = 0; row < 6 * n; ++row)
      for (int x = 0; x < n; ++x) {
        if (!(r.texels.at(x, row, 3) > 0)) continue;
        const Eigen::Vector3f d = texel_direction_reference(row / n, x, row % n, n);
        const float want = paint(k + box_exit(lo - k, hi - k, d) * d);
        const double e = r.texels.at(x, row, 0) / want - 1.0;
        err2 += e * e;
        ++seen;
      }
    EXPECT_GT(seen, 3 * n * n);  // the upper hemisphere
    return std::sqrt(err2 / seen);
  };
  // Bilinear sampling of a smooth paint on a 384 px fisheye: well under a percent.
  EXPECT_LT(rms_error(view), 0.01);
  FisheyeView distant = view;
  distant.room.reset();
  EXPECT_GT(rms_error(distant), 0.1);
}

// --- Synthetic sequences: a uniform sky seen by the upward fisheye ---

constexpr int kFace = 16, kImage = 128;

const KannalaBrandtCamera& up_camera() {
  static const KannalaBrandtCamera camera = KannalaBrandtCamera::equidistant(kImage, 190);
  return camera;
}

FisheyeView up_view() {
  return view_of(up_camera(), upward_R_camera_world());
}

ImageRGBAF uniform_image(const Eigen::Vector3f& rgb, float quality) {
  ImageRGBAF im(kImage, kImage);
  for (int y = 0; y < kImage; ++y)
    for (int x = 0; x < kImage; ++x) {
      for (int c = 0; c < 3; ++c) im.at(x, y, c) = rgb[c];
      im.at(x, y, 3) = quality;
    }
  return im;
}

ImageRGBAF filled_texels(float value, float alpha) {
  ImageRGBAF t = make_texels(kFace);
  for (int y = 0; y < 6 * kFace; ++y)
    for (int x = 0; x < kFace; ++x) {
      for (int c = 0; c < 3; ++c) t.at(x, y, c) = value;
      t.at(x, y, 3) = alpha;
    }
  return t;
}

// Texels the fisheye sees (by the reference's projection).
std::vector<std::pair<int, int>> seen_texels(const FisheyeView& view, const ImageRGBAF& image) {
  std::vector<std::pair<int, int>> seen;
  for (int row = 0; row < 6 * kFace; ++row)
    for (int x = 0; x < kFace; ++x)
      if (sample_fisheye_reference(image, view,
                                   texel_direction_reference(row / kFace, x, row % kFace, kFace)))
        seen.emplace_back(x, row);
  return seen;
}

TEST(EnvmapUpdateSequence, FirstObservationReplaces) {
  const FisheyeView view = up_view();
  const ImageRGBAF image = uniform_image({2, 3, 4}, 0.5F);
  const auto seen = seen_texels(view, image);
  ASSERT_GT(seen.size(), static_cast<std::size_t>(3 * kFace * kFace));  // a hemisphere and more
  for (UpdateRule rule : {UpdateRule::Kalman, UpdateRule::BestScore}) {
    UpdateParams p;
    p.rule = rule;
    EnvmapUpdate stage(cl_context(), p);
    // Unobserved texels holding a value seeded from another keyframe.
    const Texels r =
        device_update(stage, image, view, true, filled_texels(1000, 0), filled_texels(0, 0));
    for (const auto& [x, row] : seen) {
      ASSERT_EQ(r.texels.at(x, row, 0), 2.0F) << to_string(rule);
      ASSERT_EQ(r.texels.at(x, row, 1), 3.0F);
      ASSERT_EQ(r.texels.at(x, row, 2), 4.0F);
      ASSERT_GT(r.texels.at(x, row, 3), 0.0F);
    }
    // The top face is seen whole; the bottom face never.
    EXPECT_EQ(r.texels.at(kFace / 2, 4 * kFace + kFace / 2, 0), 2.0F);
    EXPECT_EQ(r.texels.at(kFace / 2, 5 * kFace + kFace / 2, 0), 1000.0F);
    EXPECT_EQ(r.texels.at(kFace / 2, 5 * kFace + kFace / 2, 3), 0.0F);
  }
}

TEST(EnvmapUpdateSequence, SaturatedSamplesNeverUpdate) {
  const FisheyeView view = up_view();
  ImageRGBAF image = uniform_image({5, 5, 5}, 0.8F);
  for (int y = 0; y < kImage; ++y)
    for (int x = 0; x < kImage / 2; ++x) image.at(x, y, 3) = 0.0F;  // saturated left half
  for (UpdateRule rule : {UpdateRule::Kalman, UpdateRule::BestScore}) {
    UpdateParams p;
    p.rule = rule;
    EnvmapUpdate stage(cl_context(), p);
    const ImageRGBAF before = filled_texels(1, 0.01F);
    const Texels r = device_update(stage, image, view, true, before, filled_texels(0, 0));
    int changed = 0, kept = 0;
    for (int row = 0; row < 6 * kFace; ++row)
      for (int x = 0; x < kFace; ++x) {
        const auto dir = texel_direction_reference(row / kFace, x, row % kFace, kFace);
        // Where the whole bilinear footprint lies in the saturated half, nothing may change.
        const auto s = sample_fisheye_reference(uniform_image({5, 5, 5}, 0.8F), view, dir);
        if (!s) continue;
        const auto px = up_camera().project(view.R_camera_world * dir.cast<double>());
        ASSERT_TRUE(px.has_value());
        if (px->x() < kImage / 2 - 1) {
          EXPECT_EQ(r.texels.at(x, row, 0), 1.0F) << to_string(rule);
          EXPECT_EQ(r.texels.at(x, row, 3), 0.01F);
          ++kept;
        } else if (px->x() > kImage / 2 + 1) {
          changed += r.texels.at(x, row, 0) != 1.0F ? 1 : 0;
        }
      }
    EXPECT_GT(kept, kFace * kFace);
    EXPECT_GT(changed, kFace * kFace);  // the other half did update
  }
}

TEST(EnvmapUpdateSequence, KalmanConvergesToTheTrueValueUnderNoise) {
  const FisheyeView view = up_view();
  UpdateParams p;
  p.rule = UpdateRule::Kalman;
  p.measurement_sigma = 0.05F;
  p.process_sigma = 0.0F;  // a static scene: the filter becomes the running mean
  EnvmapUpdate stage(cl_context(), p);
  auto& ctx = cl_context();
  Device4 texels(ctx, filled_texels(0, 0)), pending(ctx, filled_texels(0, 0));
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0, 0.05F);
  const Eigen::Vector3f truth(1.0F, 10.0F, 100.0F);
  const int frames = 200;
  double first_err2 = 0;
  int count = 0;
  for (int i = 0; i < frames; ++i) {
    ImageRGBAF image = uniform_image(truth, 1.0F);
    for (int y = 0; y < kImage; ++y)
      for (int x = 0; x < kImage; ++x)
        for (int c = 0; c < 3; ++c) image.at(x, y, c) *= 1.0F + noise(rng);
    const Device4 im(ctx, image);
    stage.update(im, view, false, texels, pending);
    if (i == 0) {
      const ImageRGBAF t = texels.download(ctx.queue());
      for (const auto& [x, row] : seen_texels(view, image)) {
        const double e = t.at(x, row, 1) / truth[1] - 1;
        first_err2 += e * e;
        ++count;
      }
    }
  }
  const ImageRGBAF t = texels.download(ctx.queue());
  double err2 = 0;
  double variance = 0;
  const auto seen = seen_texels(view, uniform_image(truth, 1.0F));
  for (const auto& [x, row] : seen)
    for (int c = 0; c < 3; ++c) {
      const double e = t.at(x, row, c) / truth[c] - 1;
      err2 += e * e;
    }
  for (const auto& [x, row] : seen) variance += t.at(x, row, 3);
  const double rms = std::sqrt(err2 / (3.0 * seen.size()));
  const double first_rms = std::sqrt(first_err2 / count);
  // One bilinear sample of four pixels has ~2.5 % noise; the mean of 200 about 0.2 %.
  EXPECT_GT(first_rms, 0.015);
  EXPECT_LT(rms, 0.005);
  // The filter's own variance says the same: sigma^2 / frames.
  EXPECT_NEAR(variance / seen.size(), 0.05 * 0.05 / frames, 1e-6);
}

TEST(EnvmapUpdateSequence, KalmanRestartsWhenTheLightChanges) {
  const FisheyeView view = up_view();
  EnvmapUpdate stage(cl_context(), UpdateParams{});
  auto& ctx = cl_context();
  Device4 texels(ctx, filled_texels(0, 0)), pending(ctx, filled_texels(0, 0));
  for (int i = 0; i < 20; ++i)
    stage.update(Device4(ctx, uniform_image({1, 1, 1}, 1)), view, false, texels, pending);
  stage.update(Device4(ctx, uniform_image({3, 3, 3}, 1)), view, false, texels, pending);
  const ImageRGBAF t = texels.download(ctx.queue());
  EXPECT_EQ(t.at(kFace / 2, 4 * kFace + kFace / 2, 0), 3.0F);  // a lamp came on: replaced
}

TEST(EnvmapUpdateSequence, BestScoreKeepsTheCycleBestAndPublishesAtItsEnd) {
  const FisheyeView view = up_view();
  UpdateParams p;
  p.rule = UpdateRule::BestScore;
  EnvmapUpdate stage(cl_context(), p);
  auto& ctx = cl_context();
  Device4 texels(ctx, filled_texels(7, 0.3F)), pending(ctx, filled_texels(0, 0));
  // L, M, H, M: the medium frame has the best quality, the high one is saturated.
  const std::array<std::pair<float, float>, 4> cycle{
      {{1.0F, 0.2F}, {2.0F, 0.9F}, {3.0F, 0.0F}, {4.0F, 0.5F}}};
  const int cx = kFace / 2, top = 4 * kFace + kFace / 2;
  for (int i = 0; i < 4; ++i) {
    const auto [value, q] = cycle[static_cast<std::size_t>(i)];
    stage.update(Device4(ctx, uniform_image({value, value, value}, q)), view, i == 3, texels,
                 pending);
    const ImageRGBAF t = texels.download(ctx.queue());
    if (i < 3) {
      EXPECT_EQ(t.at(cx, top, 0), 7.0F) << "published before the cycle ended, frame " << i;
    } else {
      EXPECT_EQ(t.at(cx, top, 0), 2.0F);
      EXPECT_FLOAT_EQ(t.at(cx, top, 3), 0.9F);
    }
  }
  const ImageRGBAF pend = pending.download(ctx.queue());
  EXPECT_EQ(pend.at(cx, top, 3), 0.0F);  // cleared for the next cycle
  // A cycle with nothing usable keeps the published value.
  for (int i = 0; i < 4; ++i)
    stage.update(Device4(ctx, uniform_image({9, 9, 9}, 0)), view, i == 3, texels, pending);
  EXPECT_EQ(texels.download(ctx.queue()).at(cx, top, 0), 2.0F);
}

}  // namespace
}  // namespace probeless::envmap
