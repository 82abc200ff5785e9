// Not a timed test: a way to run the renderer benchmark by hand until `probeless bench`
// has a command for it (docs/rendering.md, docs/performance.md):
//   build/release/tests/test_unit_render --gtest_also_run_disabled_tests
//       --gtest_filter='*DISABLED_Bench*'
#include "lab/bench/render_bench.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "app/render/split_sum.hpp"

namespace probeless::render {
namespace {

TEST(RenderBench, DISABLED_Bench640x480) {
  Renderer renderer;
  const RenderBenchResult r = bench_render(renderer, PinholeIntrinsics{}, 200);
  std::printf(
      "render bench: %s, %zu triangles, 640x480, %d frames: p50 %.2f ms, p90 %.2f ms, "
      "max %.2f ms, first %.2f ms\n",
      renderer.context().renderer().c_str(), r.triangles, r.frames, r.p50_ms, r.p90_ms, r.max_ms,
      r.first_ms);
  EXPECT_EQ(r.frames, 200);
}

// Every material on the pawn and on the sphere, display and float targets.
TEST(RenderBench, DISABLED_BenchMaterials640x480) {
  Renderer renderer;
  using S = Material::Shading;
  const std::pair<S, const char*> kinds[] = {
      {S::Lambert, "lambert"},       {S::Mirror, "mirror"},        {S::RoughMetal, "rough_metal"},
      {S::Refraction, "refraction"}, {S::ShDiffuse, "sh_diffuse"}, {S::PrtDiffuse, "prt_diffuse"}};
  for (const char* shape : {"pawn", "sphere"})
    for (ColourOutput output : {ColourOutput::Display8, ColourOutput::LinearFloat})
      for (const auto& [shading, name] : kinds) {
        RenderBenchScene scene;
        scene.shape = shape;
        scene.output = output;
        scene.material.shading = shading;
        scene.material.base_colour = {0.75f, 0.18f, 0.12f, 1.f};
        scene.material.roughness = 0.4f;
        const RenderBenchResult r = bench_render(renderer, PinholeIntrinsics{}, 100, scene);
        std::printf(
            "material bench: %-6s %-5s %-11s %5zu tris: wall min %.2f p50 %.2f p90 %.2f ms, "
            "cpu min %.2f p50 %.2f ms, first %.1f ms\n",
            shape, output == ColourOutput::Display8 ? "rgba8" : "f32", name, r.triangles, r.min_ms,
            r.p50_ms, r.p90_ms, r.cpu_min_ms, r.cpu_p50_ms, r.first_ms);
        EXPECT_EQ(r.frames, 100);
      }
}

// Upload + GGX prefilter per light update, for the keyframe face sizes; and the split-sum
// table, made once.
TEST(RenderBench, DISABLED_BenchPrefilter) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<float> table = make_split_sum_table(32);
  std::printf(
      "split-sum table 32x32, 512 samples: %.1f ms (once)\n",
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  for (int samples : {16, 32, 64}) {
    RendererConfig config;
    config.prefilter.samples = samples;
    Renderer renderer(config);
    for (int face : {64, 128, 256}) {
      const RenderBenchResult r = bench_prefilter(renderer, face, 20);
      std::printf(
          "prefilter bench: face %3d, %d samples at level 1: wall min %.2f p50 %.2f p90 %.2f ms, "
          "cpu min %.2f p50 %.2f ms, first %.1f ms\n",
          face, samples, r.min_ms, r.p50_ms, r.p90_ms, r.cpu_min_ms, r.cpu_p50_ms, r.first_ms);
      EXPECT_EQ(r.frames, 20);
    }
  }
}

}  // namespace
}  // namespace probeless::render
