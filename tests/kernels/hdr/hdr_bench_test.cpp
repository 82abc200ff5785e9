// Timings of the light-capture kernels on a 1024x1024 12-bit raw frame (issue #5's fisheye
// size). DISABLED_: run on demand and read the printed numbers (docs/performance.md "Light
// capture"); no thresholds, the machine is shared.
//   build/release/tests/test_kernels_hdr --gtest_also_run_disabled_tests --gtest_filter='*Bench*'
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <random>
#include <vector>

#include "kernels/hdr/exposure_count.hpp"
#include "kernels/hdr/hdr_conversion.hpp"
#include "support/cl_context.hpp"

namespace probeless {
namespace {

template <typename F>
void time_it(const char* name, int runs, F&& f) {
  auto& ctx = testing::cl_context();
  for (int i = 0; i < 10; ++i) f();  // warm-up: program build, first-touch of buffers
  ctx.queue().finish();
  std::vector<double> ms;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    ctx.queue().finish();
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  std::cout << "[ BENCH    ] " << name << ": p50 " << ms[ms.size() / 2] << " ms, p99 "
            << ms[ms.size() * 99 / 100] << " ms over " << runs << " runs (" << ctx.describe()
            << ")\n";
}

TEST(HdrBench, DISABLED_ConversionAndCount1024x1024x12bit) {
  auto& ctx = testing::cl_context();
  ImageRGB16 host(1024, 1024);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> level(0, 4095);
  for (auto& v : host.elements()) v = static_cast<std::uint16_t>(level(rng));
  const DeviceImage<std::uint16_t, 3> raw(ctx, host);
  HdrConversionParams params;
  params.circle_cx = params.circle_cy = 511.5f;
  params.circle_radius = 512.0f;
  HdrConversion conversion(ctx, params);
  DeviceImage<float, 4> out;
  const Exposure exposure{0.01, 6.0};
  time_it("HdrConversion::convert 1024x1024 12-bit", 300,
          [&] { conversion.convert(raw, 12, 256, exposure, out); });
  ExposureCount counter(ctx);
  time_it("ExposureCount::count 1024x1024 12-bit", 300,
          [&] { (void)counter.count(raw, 12, 256, 1.2, 20.0); });
  DeviceImage<std::uint16_t, 3> upload;
  time_it("upload of the raw frame (6 MB)", 100, [&] { upload.upload(ctx.queue(), host); });
}

}  // namespace
}  // namespace probeless
