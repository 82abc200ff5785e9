// Timings of the keyframe update's pieces on a 1024 px 12-bit frame seen by the upward fisheye
// with 128 px faces (issue #5's sizes). DISABLED_: run on demand and read the printed numbers
// (docs/performance.md "Light capture: bench light"); no thresholds, the machine is shared.
// The variants run interleaved, one call of each per round, so that they share the load.
//   build/release/tests/test_kernels_envmap --gtest_also_run_disabled_tests
//       --gtest_filter='*Bench*'
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <ctime>
#include <functional>
#include <iostream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "envmap_test_support.hpp"
#include "kernels/envmap/envmap_update.hpp"
#include "kernels/envmap/push_pull.hpp"
#include "kernels/hdr/hdr_conversion.hpp"
#include "support/cl_context.hpp"

namespace probeless::envmap {
namespace {

using namespace envmap::testing;

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

struct Variant {
  Variant(std::string n, std::function<void()> r) : name(std::move(n)), run(std::move(r)) {}
  std::string name;
  std::function<void()> run;
  std::vector<double> wall, cpu;
};

void run_interleaved(std::vector<Variant>& variants, int rounds) {
  auto& ctx = probeless::testing::cl_context();
  for (int i = 0; i < 5; ++i)
    for (auto& v : variants) v.run();  // program builds, first touch
  ctx.queue().finish();
  for (int r = 0; r < rounds; ++r)
    for (auto& v : variants) {
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = cpu_ms();
      v.run();
      ctx.queue().finish();
      v.cpu.push_back(cpu_ms() - c0);
      v.wall.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
  const auto p50 = [](std::vector<double> x) {
    std::sort(x.begin(), x.end());
    return x[x.size() / 2];
  };
  for (const auto& v : variants)
    std::cout << "[ BENCH    ] " << v.name << ": wall p50 " << p50(v.wall) << " ms, cpu p50 "
              << p50(v.cpu) << " ms over " << rounds << " rounds\n";
  std::cout << "[ BENCH    ] " << ctx.describe() << "\n";
}

TEST(EnvmapBench, DISABLED_UpdatePieces1024) {
  auto& ctx = probeless::testing::cl_context();
  const int size = 1024, n = 128;
  std::mt19937 rng(3);
  const ImageRGB16 host = random_raw(rng, size, size);
  const DeviceImage<std::uint16_t, 3> raw(ctx, host);
  HdrConversionParams hdr;
  hdr.circle_cx = hdr.circle_cy = 0.5F * (size - 1);
  hdr.circle_radius = 0.5F * size;
  FisheyeView view = view_of(KannalaBrandtCamera::equidistant(size, 190), upward_R_camera_world());
  FisheyeView yawed = view;  // the rig turned: texel rows cross the image's rows
  yawed.R_camera_world =
      view.R_camera_world * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  FisheyeView parallax = view;
  parallax.room = RoomBox{{-2.5, -2.5, 0}, {2.5, 2.5, 2.7}};
  parallax.keyframe_position = {0.1, -1.0, 1.2};
  parallax.position = {0.3, -0.8, 1.2};
  EnvmapUpdate update(ctx, {}, hdr);
  HdrConversion conversion(ctx, hdr);
  PushPull push_pull(ctx);
  DeviceImage<float, 4> converted;
  conversion.convert(raw, 12, 256, {0.01, 0}, converted);
  DeviceImage<float, 4> texels(ctx, random_texels(rng, n)), pending(ctx, make_texels(n));
  DeviceImage<std::uint16_t, 3> upload;
  const Exposure e{0.01, 0};
  // The sim (or a camera driver) has just written the frame: both variants start from a
  // frame written by the CPU (a 6 MB copy, counted in both).
  ImageRGB16 frame = host;
  const auto write_frame = [&] { std::memcpy(frame.data(), host.data(), host.size_bytes()); };
  std::vector<Variant> v;
  v.push_back({"write + upload + update_raw", [&] {
                 write_frame();
                 upload.upload(ctx.queue(), frame);
                 update.update_raw(upload, 12, 256, e, view, false, texels, pending);
               }});
  v.push_back({"write + wrap_host + update_raw", [&] {
                 write_frame();
                 const auto wrapped =
                     DeviceImage<std::uint16_t, 3>::wrap_host(ctx.context(), frame);
                 update.update_raw(wrapped, 12, 256, e, view, false, texels, pending);
                 ctx.queue().finish();
               }});
  v.push_back({"write + wrap_host + update_raw, yawed", [&] {
                 write_frame();
                 const auto wrapped =
                     DeviceImage<std::uint16_t, 3>::wrap_host(ctx.context(), frame);
                 update.update_raw(wrapped, 12, 256, e, yawed, false, texels, pending);
                 ctx.queue().finish();
               }});
  v.push_back({"write + wrap_host + update_raw + parallax", [&] {
                 write_frame();
                 const auto wrapped =
                     DeviceImage<std::uint16_t, 3>::wrap_host(ctx.context(), frame);
                 update.update_raw(wrapped, 12, 256, e, parallax, false, texels, pending);
                 ctx.queue().finish();
               }});
  v.push_back({"write + upload + convert + update", [&] {
                 write_frame();
                 upload.upload(ctx.queue(), frame);
                 conversion.convert(upload, 12, 256, e, converted);
                 update.update(converted, view, false, texels, pending);
               }});
  v.push_back({"write frame (6 MB copy)", write_frame});
  v.push_back({"push-pull", [&] { push_pull.fill(texels); }});
  run_interleaved(v, 100);
}

// Push-pull alone, on what an upward fisheye leaves: five faces half observed, the floor
// (-z) empty, so that the pass across face edges has one face to fill.
TEST(EnvmapBench, DISABLED_PushPull128) {
  auto& ctx = probeless::testing::cl_context();
  const int n = 128;
  std::mt19937 rng(4);
  ImageRGBAF host = random_texels(rng, n);
  for (int y = 5 * n; y < 6 * n; ++y)
    for (int x = 0; x < n; ++x) host.at(x, y, 3) = 0.0F;
  DeviceImage<float, 4> texels(ctx, host);
  PushPull push_pull(ctx);
  std::vector<Variant> v;
  v.push_back({"push-pull, floor empty", [&] {
                 texels.upload(ctx.queue(), host, false);
                 push_pull.fill(texels);
               }});
  v.push_back({"upload texels alone", [&] { texels.upload(ctx.queue(), host, false); }});
  run_interleaved(v, 200);
}

}  // namespace
}  // namespace probeless::envmap
