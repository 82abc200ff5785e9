// Not a timed test: a way to run the renderer benchmark by hand until `probeless bench`
// has a command for it (docs/rendering.md):
//   build/release/tests/test_unit_render --gtest_also_run_disabled_tests
//       --gtest_filter='*DISABLED_Bench*'
#include "app/render/render_bench.hpp"

#include <gtest/gtest.h>

#include <cstdio>

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

}  // namespace
}  // namespace probeless::render
