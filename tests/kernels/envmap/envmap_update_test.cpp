#include "kernels/envmap/envmap_update.hpp"

#include <gtest/gtest.h>

#include <random>

#include "envmap_test_support.hpp"
#include "kernels/envmap/envmap_update_reference.hpp"
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
      const FisheyeView view = random_view(rng, image_size);
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

INSTANTIATE_TEST_SUITE_P(Rules, EnvmapUpdateTest,
                         ::testing::Values(UpdateRule::Kalman, UpdateRule::BestScore),
                         [](const auto& param_info) {
                           return std::string(param_info.param == UpdateRule::Kalman ? "Kalman"
                                                                                     : "BestScore");
                         });

// The reference's projection (a polynomial arctangent, as the kernel's) lands where core's
// KannalaBrandtCamera::project does: sampling a linear ramp image returns the pixel position.
TEST(EnvmapUpdateReference, ProjectsLikeTheCameraModel) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int trial = 0; trial < 5; ++trial) {
    const FisheyeView view = random_view(rng, 300);
    ImageRGBAF ramp(300, 300);
    for (int y = 0; y < 300; ++y)
      for (int x = 0; x < 300; ++x) {
        ramp.at(x, y, 0) = static_cast<float>(x);
        ramp.at(x, y, 1) = static_cast<float>(y);
        ramp.at(x, y, 3) = 1.0F;
      }
    const KannalaBrandtCamera camera(view.camera);
    int compared = 0;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3f d(u(rng), u(rng), u(rng));
      const auto s = sample_fisheye_reference(ramp, view, d);
      const auto px = camera.project(view.R_camera_world * d.cast<double>());
      if (!s) continue;
      ASSERT_TRUE(px.has_value());
      EXPECT_NEAR((*s)[0], px->x(), 2e-3);
      EXPECT_NEAR((*s)[1], px->y(), 2e-3);
      ++compared;
    }
    EXPECT_GT(compared, 500);
  }
}

// --- Synthetic sequences: a uniform sky seen by the upward fisheye ---

constexpr int kFace = 16, kImage = 128;

FisheyeView up_view() {
  FisheyeView v;
  v.camera = KannalaBrandtCamera::equidistant(kImage, 190).params();
  v.R_camera_world = upward_R_camera_world();
  return v;
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
        const KannalaBrandtCamera cam(view.camera);
        const auto px = cam.project(view.R_camera_world * dir.cast<double>());
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
