#include "kernels/composite/hdr_compositor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "kernels/composite/hdr_composite_reference.hpp"
#include "support/cl_context.hpp"

namespace probeless {
namespace {

using testing::cl_context;
using ImageRGBAF = Image<float, 4>;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

float next_up(float x, int ulps) {
  for (int i = 0; i < ulps; ++i) x = std::nextafter(x, kInf);
  for (int i = 0; i > ulps; --i) x = std::nextafter(x, -kInf);
  return x;
}

// The first float of the encode table's entry j.
float entry_start(const CameraCurve& curve, int j) {
  return std::bit_cast<float>(static_cast<std::uint32_t>(curve.index_base() + j)
                              << CameraCurve::kIndexShift);
}

// round(255 x^(1/gamma)) in double: the definition encode() implements with float thresholds.
int encode_exact(double x, double gamma) {
  return static_cast<int>(std::floor(255.0 * std::pow(std::clamp(x, 0.0, 1.0), 1.0 / gamma) + 0.5));
}

// --- the curve -------------------------------------------------------------------------

TEST(CameraCurve, DecodeThenEncodeGivesEveryByteBack) {
  for (const double gamma : {1.0, 1.8, 2.2, 2.4, 3.0}) {
    const CameraCurve curve(gamma);
    for (int v = 0; v < 256; ++v) {
      const auto b = static_cast<std::uint8_t>(v);
      EXPECT_EQ(curve.encode(curve.decode(b)), v) << "gamma " << gamma;
      EXPECT_EQ(curve.encode_fast(curve.decode(b)), v) << "gamma " << gamma;
    }
    EXPECT_EQ(curve.decode(0), 0.0F);
    EXPECT_EQ(curve.decode(255), 1.0F);  // a clipped channel decodes to the clip
  }
}

TEST(CameraCurve, EncodeIsRoundedInverseGamma) {
  const CameraCurve curve(2.2);
  EXPECT_EQ(curve.encode(0.0F), 0);
  EXPECT_EQ(curve.encode(-1.0F), 0);
  EXPECT_EQ(curve.encode(kNaN), 0);
  EXPECT_EQ(curve.encode(1.0F), 255);
  EXPECT_EQ(curve.encode(7.0F), 255);
  EXPECT_EQ(curve.encode(0.5F), 186);   // 255 * 0.5^(1/2.2) = 186.1
  EXPECT_EQ(curve.encode(0.2F), 123);   // 255 * 0.2^(1/2.2) = 122.7
  EXPECT_EQ(curve.encode(0.21F), 125);  // 125.4
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  int mismatches = 0;
  for (int i = 0; i < 200000; ++i) {
    const float x = u(rng) * u(rng) * u(rng);  // denser towards black, where the curve is steep
    const double exact = 255.0 * std::pow(static_cast<double>(x), 1.0 / 2.2);
    // Away from a rounding boundary the float thresholds give the exact rounding.
    if (std::abs(exact - std::floor(exact) - 0.5) > 1e-4)
      mismatches += curve.encode(x) != encode_exact(x, 2.2);
  }
  EXPECT_EQ(mismatches, 0);
}

// The device's path (float-bits table, then steps) against the threshold count, on dense samples
// and on every float near a threshold or an index boundary, for several gammas.
TEST(CameraCurve, FastEncodeEqualsTheThresholdCount) {
  for (const double gamma : {0.4, 1.0, 1.8, 2.2, 2.4, 2.8, 4.0, 10.0}) {
    const CameraCurve curve(gamma);
    int mismatches = 0;
    const auto check = [&](float x) { mismatches += curve.encode_fast(x) != curve.encode(x); };
    for (int v = 1; v < 256; ++v)
      for (int u = -8; u <= 8; ++u) check(next_up(curve.thresholds()[v], u));
    for (int j = 0; j <= curve.index_last(); ++j)
      for (int u = -8; u <= 8; ++u) check(next_up(entry_start(curve, j), u));
    // Every 4096th float bit pattern in [0, 1]: ~260 000 values across all exponents.
    for (std::uint32_t bits = 0; bits <= 0x3f800000U; bits += 4096)
      check(std::bit_cast<float>(bits));
    EXPECT_EQ(mismatches, 0) << "gamma " << gamma;
  }
  // The cost of the fast path: one compare per channel for camera curves.
  for (const double gamma : {1.0, 1.8, 2.2, 2.4, 2.8, 4.0, 10.0})
    EXPECT_EQ(CameraCurve(gamma).steps(), 1) << gamma;
  EXPECT_GT(CameraCurve(0.4).steps(), 1);  // steep: the extra steps ran above
}

// --- the composite, by hand ------------------------------------------------------------

struct Case {
  std::string what;
  std::array<std::uint8_t, 3> real;
  std::array<float, 4> layer;  // premultiplied radiance, coverage
  float matte;
  std::array<int, 3> expected;
};

const CameraResponse kCamera{{0.8, 1.0, 1.6}, 2.2};  // a white balance, gamma 2.2

// The hand-made cases, in radiance units of kCamera. d(v) is the linear value of byte v.
std::vector<Case> hand_cases() {
  const CameraCurve curve(2.2);
  const auto d = [&](int v) { return curve.decode(static_cast<std::uint8_t>(v)); };
  const auto& e = kCamera.exposure;
  const auto E = [&](int c) { return static_cast<float>(e[static_cast<std::size_t>(c)]); };
  std::vector<Case> cases;
  // Real: no virtual layer; any matte leaves the bytes as they were.
  cases.push_back({"real, matte 1", {12, 130, 250}, {0, 0, 0, 0}, 1.0F, {12, 130, 250}});
  cases.push_back({"real, matte 0.5", {12, 130, 250}, {0, 0, 0, 0}, 0.5F, {12, 130, 250}});
  // Virtual: an object whose radiance is e * 0.5 in every channel shows as linear 0.5 (186).
  const std::array<float, 4> grey_object{0.5F * E(0), 0.5F * E(1), 0.5F * E(2), 1.0F};
  cases.push_back({"virtual, matte 1", {12, 130, 250}, grey_object, 1.0F, {186, 186, 186}});
  cases.push_back({"virtual, matte 0 (behind a real surface)",
                   {12, 130, 250},
                   grey_object,
                   0.0F,
                   {12, 130, 250}});
  // Matte 0.5: halfway in radiance, not in bytes: encode(0.5 * 0.5 + 0.5 * d(real)).
  cases.push_back({"virtual, matte 0.5",
                   {12, 130, 250},
                   grey_object,
                   0.5F,
                   {encode_exact(0.25 + 0.5 * d(12), 2.2), encode_exact(0.25 + 0.5 * d(130), 2.2),
                    encode_exact(0.25 + 0.5 * d(250), 2.2)}});
  // Sum: a shadow taking half the real radiance away, at full, half and no visibility.
  const std::array<std::uint8_t, 3> table{200, 180, 160};
  const std::array<float, 4> half_shadow{-0.5F * E(0) * d(200), -0.5F * E(1) * d(180),
                                         -0.5F * E(2) * d(160), 0.0F};
  cases.push_back({"sum, negative, matte 1",
                   table,
                   half_shadow,
                   1.0F,
                   {encode_exact(0.5 * d(200), 2.2), encode_exact(0.5 * d(180), 2.2),
                    encode_exact(0.5 * d(160), 2.2)}});
  cases.push_back({"sum, negative, matte 0.5 (soft occluder edge)",
                   table,
                   half_shadow,
                   0.5F,
                   {encode_exact(0.75 * d(200), 2.2), encode_exact(0.75 * d(180), 2.2),
                    encode_exact(0.75 * d(160), 2.2)}});
  cases.push_back({"sum, negative, matte 0 (a real hand over the shadow)",
                   table,
                   half_shadow,
                   0.0F,
                   {200, 180, 160}});
  // A shadow deeper than the real radiance: clamped at 0 radiance, black.
  cases.push_back(
      {"sum below zero", table, {-3.0F * E(0), -3.0F * E(1), -3.0F * E(2), 0.0F}, 1.0F, {0, 0, 0}});
  // Light added (an inter-reflection): positive sum, clipped at the top.
  cases.push_back({"sum, positive",
                   {100, 100, 250},
                   {0.1F * E(0), 0.1F * E(1), 0.5F * E(2), 0.0F},
                   1.0F,
                   {encode_exact(d(100) + 0.1, 2.2), encode_exact(d(100) + 0.1, 2.2), 255}});
  // Saturated real pixels are taken at the clip (linear 1): a half shadow gives 0.5 (186).
  cases.push_back({"saturated, shadow",
                   {255, 255, 255},
                   {-0.5F * E(0), -0.5F * E(1), -0.5F * E(2), 0.0F},
                   1.0F,
                   {186, 186, 186}});
  cases.push_back({"one channel saturated, shadow",
                   {255, 120, 40},
                   {-0.5F * E(0), -0.5F * E(1) * d(120), -0.5F * E(2) * d(40), 0.0F},
                   1.0F,
                   {186, encode_exact(0.5 * d(120), 2.2), encode_exact(0.5 * d(40), 2.2)}});
  cases.push_back(
      {"saturated, light added", {255, 255, 255}, {E(0), E(1), E(2), 0.0F}, 1.0F, {255, 255, 255}});
  // The object's edge over its own shadow: half coverage, premultiplied object 0.5 * (e * 0.5)
  // plus half a receiver whose delta removes half the real radiance.
  cases.push_back(
      {"edge of the object over its shadow",
       table,
       {0.5F * grey_object[0] + 0.5F * half_shadow[0],
        0.5F * grey_object[1] + 0.5F * half_shadow[1],
        0.5F * grey_object[2] + 0.5F * half_shadow[2], 0.5F},
       1.0F,
       {encode_exact(0.25 + 0.5 * 0.5 * d(200), 2.2), encode_exact(0.25 + 0.5 * 0.5 * d(180), 2.2),
        encode_exact(0.25 + 0.5 * 0.5 * d(160), 2.2)}});
  // What stages must never produce but the compositor must survive.
  cases.push_back({"NaN matte", {12, 130, 250}, grey_object, kNaN, {12, 130, 250}});
  cases.push_back({"matte above 1", {12, 130, 250}, grey_object, 3.0F, {186, 186, 186}});
  cases.push_back({"NaN coverage counts as 0 (the layer adds)",
                   {0, 0, 0},
                   {0.5F * E(0), 0.5F * E(1), 0.5F * E(2), kNaN},
                   1.0F,
                   {186, 186, 186}});
  cases.push_back(
      {"NaN radiance is black", {12, 130, 250}, {kNaN, kNaN, kNaN, 1.0F}, 1.0F, {0, 0, 0}});
  cases.push_back({"infinite radiance is white",
                   {12, 130, 250},
                   {kInf, kInf, kInf, 1.0F},
                   1.0F,
                   {255, 255, 255}});
  return cases;
}

void fill(const std::vector<Case>& cases, ImageRGB8& real, ImageRGBAF& layer, ImageF& matte) {
  const int n = static_cast<int>(cases.size());
  real = ImageRGB8(n, 1);
  layer = ImageRGBAF(n, 1);
  matte = ImageF(n, 1);
  for (int i = 0; i < n; ++i) {
    const auto& k = cases[static_cast<std::size_t>(i)];
    for (int c = 0; c < 3; ++c) real.at(i, 0, c) = k.real[static_cast<std::size_t>(c)];
    for (int c = 0; c < 4; ++c) layer.at(i, 0, c) = k.layer[static_cast<std::size_t>(c)];
    matte.at(i, 0) = k.matte;
  }
}

TEST(HdrCompositeReference, HandMadeCases) {
  const auto cases = hand_cases();
  ImageRGB8 real;
  ImageRGBAF layer;
  ImageF matte;
  fill(cases, real, layer, matte);
  const auto out = hdr_composite_reference(real, layer, matte, kCamera);
  for (int i = 0; i < out.width(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(out.at(i, 0, c), cases[static_cast<std::size_t>(i)].expected[c])
          << cases[static_cast<std::size_t>(i)].what << ", channel " << c;
}

TEST(HdrCompositor, HandMadeCasesOnTheDevice) {
  auto& ctx = cl_context();
  HdrCompositor compositor(ctx);
  const auto cases = hand_cases();
  ImageRGB8 real;
  ImageRGBAF layer;
  ImageF matte;
  fill(cases, real, layer, matte);
  DeviceImageRGB8 out;
  compositor.process(DeviceImageRGB8(ctx, real), DeviceImage<float, 4>(ctx, layer),
                     DeviceImageF(ctx, matte), kCamera, out);
  const auto host = out.download(ctx.queue());
  for (std::size_t i = 0; i < cases.size(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(host.elements()[3 * i + static_cast<std::size_t>(c)], cases[i].expected[c])
          << cases[i].what << ", channel " << c;
}

// Given the objects' rectangle (the matte 0 outside), only its rows are visited after the
// copy of the frame: the same image as over the whole frame, whatever the output held before.
TEST(HdrCompositor, OverTheObjectsRowsTheWholeFramesImage) {
  auto& ctx = cl_context();
  HdrCompositor compositor(ctx);
  const int w = 97, h = 53;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  ImageRGB8 real(w, h), other(w, h);
  ImageRGBAF layer(w, h);
  for (auto& v : real.elements()) v = static_cast<std::uint8_t>(rng() % 256);
  for (auto& v : other.elements()) v = static_cast<std::uint8_t>(rng() % 256);
  for (auto& v : layer.elements()) v = 2.0F * u(rng);
  const PixelRect rects[] = {{10, 7, 60, 31}, {90, 40, 97, 53}, {0, 0, 1, 1}, {}};
  for (const PixelRect& rect : rects) {
    ImageF matte(w, h, 0.0F);
    for (int y = rect.y0; y < rect.y1; ++y)
      for (int x = rect.x0; x < rect.x1; ++x) matte.at(x, y) = u(rng) < 0.5F ? 1.0F : u(rng);
    const DeviceImageRGB8 d_real(ctx, real), d_other(ctx, other);
    const DeviceImage<float, 4> d_layer(ctx, layer);
    const DeviceImageF d_matte(ctx, matte), everywhere(ctx, ImageF(w, h, 1.0F));
    DeviceImageRGB8 whole, cut;
    compositor.process(d_real, d_layer, d_matte, kCamera, whole);
    compositor.process(d_other, d_layer, everywhere, kCamera, cut);
    compositor.process(d_real, d_layer, d_matte, kCamera, cut, rect);
    const auto want = whole.download(ctx.queue());
    EXPECT_EQ(cut.download(ctx.queue()), want) << rect.x0 << "," << rect.y0;
    EXPECT_EQ(want == real, rect.empty()) << "the layer shows inside the rectangle";
  }
}

// An unchanged real pixel comes back identical for every byte, whatever the exposure, also
// where the matte is on (the layer empty there) and the arithmetic runs rather than the copy.
TEST(HdrCompositor, UnchangedRealPixelsRoundTripExactly) {
  auto& ctx = cl_context();
  HdrCompositor compositor(ctx);
  ImageRGB8 real(256, 3);
  ImageRGBAF layer(256, 3, 0.0F);
  ImageF matte(256, 3);
  for (int v = 0; v < 256; ++v)
    for (int y = 0; y < 3; ++y) {
      for (int c = 0; c < 3; ++c) real.at(v, y, c) = static_cast<std::uint8_t>((v + 85 * c) % 256);
      matte.at(v, y) = y == 0 ? 0.0F : (y == 1 ? 0.5F : 1.0F);
    }
  const DeviceImageRGB8 d_real(ctx, real);
  const DeviceImage<float, 4> d_layer(ctx, layer);
  const DeviceImageF d_matte(ctx, matte);
  DeviceImageRGB8 out;
  for (const double e : {1e-3, 0.37, 1.0, 7.3, 2.5e4}) {
    for (const double gamma : {1.8, 2.2, 2.6}) {
      const CameraResponse camera{{e, 1.7 * e, 0.6 * e}, gamma};
      EXPECT_EQ(hdr_composite_reference(real, layer, matte, camera), real)
          << "e " << e << " gamma " << gamma;
      compositor.process(d_real, d_layer, d_matte, camera, out);
      EXPECT_EQ(out.download(ctx.queue()), real) << "e " << e << " gamma " << gamma;
    }
  }
}

// Auto exposure: the same object radiance under twice the exposure estimate e shows at half
// the linear display value (before gamma), so the object darkens with the real scene.
TEST(HdrCompositeReference, DoublingExposureHalvesTheObjectsLinearValue) {
  const CameraCurve curve(2.2);
  for (const float radiance : {0.01F, 0.3F, 0.9F}) {
    for (const float e : {1.0F, 1.5F, 3.0F}) {  // radiance / e <= 1: nothing clips
      const float x1 = hdr_composite_linear(90, radiance, 1.0F, 1.0F, e, 1.0F / e, curve);
      const float x2 =
          hdr_composite_linear(90, radiance, 1.0F, 1.0F, 2.0F * e, 1.0F / (2.0F * e), curve);
      EXPECT_GT(x1, 0.0F);
      EXPECT_EQ(x2, 0.5F * x1) << radiance << " " << e;  // exactly: 1 / 2e is half of 1 / e
      const auto b1 = hdr_composite_channel(90, radiance, 1.0F, 1.0F, e, 1.0F / e, curve);
      const auto b2 =
          hdr_composite_channel(90, radiance, 1.0F, 1.0F, 2.0F * e, 1.0F / (2.0F * e), curve);
      EXPECT_EQ(b2, curve.encode(0.5F * x1));
      EXPECT_LT(b2, b1);
    }
  }
  // The whole frame: an object pixel darkens with e, the real pixel beside it keeps its bytes.
  ImageRGB8 real(2, 1, 120);
  ImageRGBAF layer(2, 1, 0.0F);
  for (int c = 0; c < 4; ++c) layer.at(0, 0, c) = c < 3 ? 0.4F : 1.0F;
  ImageF matte(2, 1, 1.0F);
  const auto a = hdr_composite_reference(real, layer, matte, {{1.0, 1.0, 1.0}, 2.2});
  const auto b = hdr_composite_reference(real, layer, matte, {{2.0, 2.0, 2.0}, 2.2});
  EXPECT_EQ(a.at(0, 0), curve.encode(0.4F));
  EXPECT_EQ(b.at(0, 0), curve.encode(0.2F));
  EXPECT_LT(b.at(0, 0), a.at(0, 0));
  EXPECT_EQ(a.at(1, 0), 120);
  EXPECT_EQ(b.at(1, 0), 120);
}

// --- the device against the reference on random frames ---------------------------------

// Layers as the renderer produces them: empty, object (coverage 1), shadow or light deltas
// (coverage 0), edges (partial coverage, premultiplied mixes), plus non-finite values.
ImageRGBAF random_layer(int w, int h, std::mt19937& rng) {
  std::uniform_int_distribution<int> pick(0, 19);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  std::uniform_real_distribution<float> radiance(0.0F, 3.0F);
  std::uniform_real_distribution<float> delta(-2.0F, 0.5F);
  ImageRGBAF layer(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = &layer.at(x, y, 0);
      const int k = pick(rng);
      if (k < 6) {
        p[0] = p[1] = p[2] = p[3] = 0.0F;
      } else if (k < 11) {
        for (int c = 0; c < 3; ++c) p[c] = radiance(rng);
        p[3] = 1.0F;
      } else if (k < 15) {
        for (int c = 0; c < 3; ++c) p[c] = delta(rng);
        p[3] = 0.0F;
      } else if (k < 19) {
        const float cov = u(rng);
        for (int c = 0; c < 3; ++c) p[c] = cov * radiance(rng) + (1.0F - cov) * delta(rng);
        p[3] = cov;
      } else {
        const float specials[] = {kNaN, kInf, -kInf, 1e30F, -0.0F, 1.5F, -0.5F};
        std::uniform_int_distribution<int> s(0, 6);
        for (int c = 0; c < 4; ++c) p[c] = specials[s(rng)];
      }
    }
  return layer;
}

ImageF random_matte(int w, int h, std::mt19937& rng) {
  const float specials[] = {0.0F, 1.0F, 0.5F, -0.25F, 1.5F, kNaN, 1.0F / 255.0F, 0.998F};
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  std::uniform_int_distribution<int> pick(0, 15);
  ImageF m(w, h);
  for (auto& v : m.elements()) {
    const int p = pick(rng);
    v = p < 8 ? specials[p] : u(rng);
  }
  // Whole runs of 0, so that the copy path of 4-pixel groups runs as well.
  for (int y = 0; y < h; y += 3)
    for (int x = 0; x < w / 2; ++x) m.at(x, y) = 0.0F;
  return m;
}

TEST(HdrCompositor, MatchesTheReferenceExactlyOnEverySize) {
  auto& ctx = cl_context();
  HdrCompositor compositor(ctx);
  DeviceImageRGB8 out;
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_real_distribution<double> log_e(-2.0, 2.0);
  const double gammas[] = {2.2, 1.8, 2.6, 0.4};  // 0.4: a curve that needs several steps
  int run = 0;
  for (const auto& [w, h] : testing::kernel_test_sizes()) {
    ImageRGB8 real(w, h);
    for (auto& v : real.elements()) v = static_cast<std::uint8_t>(byte(rng));
    const auto layer = random_layer(w, h, rng);
    const auto matte = random_matte(w, h, rng);
    const CameraResponse camera{
        {std::pow(10.0, log_e(rng)), std::pow(10.0, log_e(rng)), std::pow(10.0, log_e(rng))},
        gammas[run++ % 4]};
    compositor.process(DeviceImageRGB8(ctx, real), DeviceImage<float, 4>(ctx, layer),
                       DeviceImageF(ctx, matte), camera, out);
    const auto expected = hdr_composite_reference(real, layer, matte, camera);
    const auto got = out.download(ctx.queue());
    ASSERT_EQ(got.width(), w);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < got.elements().size(); ++i)
      differ += got.elements()[i] != expected.elements()[i];
    EXPECT_EQ(differ, 0U) << w << "x" << h << " gamma " << camera.gamma;
  }
}

// The device's encode on every float near a threshold or an index boundary: layer = x with
// coverage 0 over a black real pixel, matte 1 and e = 1 composite to exactly x.
TEST(HdrCompositor, EncodesLikeTheReferenceNearEveryBoundary) {
  auto& ctx = cl_context();
  HdrCompositor compositor(ctx);
  const CameraCurve curve(2.2);
  std::vector<float> xs;
  for (int v = 1; v < 256; ++v)
    for (int u = -4; u <= 4; ++u) xs.push_back(next_up(curve.thresholds()[v], u));
  for (int j = 0; j <= curve.index_last(); ++j)
    for (int u = -4; u <= 4; ++u) xs.push_back(next_up(entry_start(curve, j), u));
  const int w = 512, h = static_cast<int>((xs.size() + w - 1) / w);
  ImageRGB8 real(w, h, 0);
  ImageRGBAF layer(w, h, 0.0F);
  for (std::size_t i = 0; i < xs.size(); ++i)
    for (int c = 0; c < 3; ++c) layer.elements()[4 * i + static_cast<std::size_t>(c)] = xs[i];
  const ImageF matte(w, h, 1.0F);
  DeviceImageRGB8 out;
  compositor.process(DeviceImageRGB8(ctx, real), DeviceImage<float, 4>(ctx, layer),
                     DeviceImageF(ctx, matte), CameraResponse{}, out);
  const auto got = out.download(ctx.queue());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < xs.size(); ++i)
    differ += got.elements()[3 * i] != curve.encode(xs[i]);
  EXPECT_EQ(differ, 0U) << "of " << xs.size();
}

// --- bad input ----------------------------------------------------------------------------

template <typename F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no std::invalid_argument)";
}

TEST(HdrCompositor, RejectsBadInput) {
  auto& ctx = cl_context();
  HdrCompositor compositor(ctx);
  const DeviceImageRGB8 real(ctx, 4, 4);
  const DeviceImage<float, 4> layer(ctx, 4, 4), small_layer(ctx, 4, 3);
  const DeviceImageF matte(ctx, 4, 4), small_matte(ctx, 3, 4);
  DeviceImageRGB8 out;
  const CameraResponse ok{};
  EXPECT_NE(message_of([&] {
              compositor.process(real, small_layer, matte, ok, out);
            }).find("differ in size"),
            std::string::npos);
  EXPECT_NE(message_of([&] {
              compositor.process(real, layer, small_matte, ok, out);
            }).find("differ in size"),
            std::string::npos);
  for (const double e : {0.0, -1.0, std::nan(""), HUGE_VAL, -HUGE_VAL, 1e31, 1e-31}) {
    CameraResponse bad;
    bad.exposure[1] = e;
    const auto what = message_of([&] { compositor.process(real, layer, matte, bad, out); });
    EXPECT_NE(what.find("exposure e[1]"), std::string::npos) << e << ": " << what;
  }
  for (const double g : {0.0, -2.2, std::nan(""), HUGE_VAL, 10.5}) {
    CameraResponse bad;
    bad.gamma = g;
    const auto what = message_of([&] { compositor.process(real, layer, matte, bad, out); });
    EXPECT_NE(what.find("gamma"), std::string::npos) << g << ": " << what;
    EXPECT_THROW(CameraCurve{g}, std::invalid_argument);
  }
  // The reference says the same.
  const ImageRGB8 h_real(4, 4);
  EXPECT_THROW(hdr_composite_reference(h_real, ImageRGBAF(4, 3), ImageF(4, 4), ok),
               std::invalid_argument);
  EXPECT_THROW(hdr_composite_reference(h_real, ImageRGBAF(4, 4), ImageF(4, 4),
                                       CameraResponse{{1.0, 0.0, 1.0}, 2.2}),
               std::invalid_argument);
  // A rejected frame leaves the compositor usable.
  compositor.process(real, layer, matte, ok, out);
  EXPECT_EQ(out.width(), 4);
}

}  // namespace
}  // namespace probeless
