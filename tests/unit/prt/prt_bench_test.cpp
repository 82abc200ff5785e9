// Not timed tests: measurements to run by hand, recorded in docs/prt.md and
// docs/performance.md:
//   build/release/tests/test_unit_prt --gtest_also_run_disabled_tests
//       --gtest_filter='PrtBench.*'
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "app/render/prt/prt.hpp"
#include "prt_test_support.hpp"
#include "sphere_plane_reference.hpp"

namespace probeless::prt {
namespace {

using testing::kOpenT0;

double load_average() {
  std::ifstream f("/proc/loadavg");
  double l = -1;
  f >> l;
  return l;
}

// RMS and max over vertices of the largest coefficient error, relative to the open T_0.
struct Error {
  double rms = 0, max = 0;
};
template <typename Reference>
Error transfer_error(const Transfer& t, const std::vector<std::size_t>& vertices,
                     Reference reference) {
  Error e;
  for (std::size_t v : vertices) {
    const double d = testing::max_abs_diff(t.at(v), reference(v)) / kOpenT0;
    e.rms += d * d;
    e.max = std::max(e.max, d);
  }
  e.rms = std::sqrt(e.rms / static_cast<double>(vertices.size()));
  return e;
}

std::vector<std::size_t> all(std::size_t n) {
  std::vector<std::size_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = i;
  return v;
}

// The error of the estimator against the sample count: the sphere against the analytic
// transfer, the ground beside it against the Monte Carlo reference, the pawn against a bake
// with 16 times the largest count here.
TEST(PrtBench, DISABLED_ErrorVsSamples) {
  const render::Mesh sphere = render::make_sphere(0.1f);
  const render::Mesh on_floor = testing::sphere_on_floor();
  const render::Mesh pawn = render::make_pawn();
  const Scene ground{.ground = testing::floor_ground()};
  const int k = Ground{}.subdivisions, centre = k / 2;
  std::vector<std::size_t> probes;
  std::vector<std::array<double, kShMaxCount>> ground_ref;
  {
    const Bake geometry = bake_prt(on_floor, ground, {.samples = 1});
    for (int step : {1, 2, 3, 5, 10, 20}) {
      probes.push_back(static_cast<std::size_t>(centre * (k + 1) + centre + step));
      ground_ref.push_back(
          testing::reference_transfer({}, geometry.ground.positions[probes.back()].cast<double>(),
                                      Eigen::Vector3d::UnitZ(), 4'000'000));
    }
  }
  const Bake pawn_ref = bake_prt(pawn, {}, {.samples = 65536});
  std::printf(
      "errors relative to the open T_0 (%.4f): rms / max over vertices of the largest "
      "of the 25 coefficients' errors\n",
      kOpenT0);
  std::printf("| samples | sphere vs analytic | ground vs MC (6 points) | pawn vs 65536 |\n");
  for (int n : {64, 128, 256, 512, 1024, 2048, 4096}) {
    const Bake s = bake_prt(sphere, {}, {.samples = n});
    const Error es = transfer_error(s.object, all(sphere.vertex_count()), [&](std::size_t v) {
      return testing::open_transfer(sphere.normals[v].cast<double>());
    });
    const Bake g = bake_prt(on_floor, ground, {.samples = n});
    std::size_t i = 0;
    const Error eg =
        transfer_error(g.ground_with_object, probes, [&](std::size_t) { return ground_ref[i++]; });
    const Bake p = bake_prt(pawn, {}, {.samples = n});
    const Error ep = transfer_error(p.object, all(pawn.vertex_count()),
                                    [&](std::size_t v) { return pawn_ref.object.at(v); });
    std::printf("| %d | %.2f %% / %.2f %% | %.2f %% / %.2f %% | %.2f %% / %.2f %% |\n", n,
                100 * es.rms, 100 * es.max, 100 * eg.rms, 100 * eg.max, 100 * ep.rms, 100 * ep.max);
  }
}

TEST(PrtBench, DISABLED_BakeTime) {
  struct Case {
    const char* what;
    render::Mesh mesh;
    Scene scene;
  };
  const Case cases[] = {
      {"sphere alone", render::make_builtin("sphere"), {}},
      {"sphere on plane", testing::sphere_on_floor(), {.ground = testing::floor_ground()}},
      {"pawn alone", render::make_builtin("pawn"), {}},
      {"pawn on plane", render::make_builtin("pawn"), {.ground = testing::floor_ground()}},
  };
  std::printf("load average at start %.2f\n", load_average());
  for (unsigned threads : {2u, 1u})
    for (const Case& c : cases) {
      // Best of 3 by wall time; process CPU time (all threads) is steadier on a shared machine.
      double best = 1e9, cpu = 0;
      Bake b;
      for (int run = 0; run < 3; ++run) {
        const std::clock_t c0 = std::clock();
        b = bake_prt(c.mesh, c.scene, {.threads = threads});
        cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC / 3;
        best = std::min(best, b.seconds);
      }
      std::printf(
          "%s: %zu + %zu vertices, %d samples, %u threads: wall best of 3 %.3f s, "
          "cpu mean %.3f s\n",
          c.what, b.object.vertex_count(), b.ground.vertex_count(), BakeOptions{}.samples, threads,
          best, cpu);
    }
  // A cache hit: hashing the mesh, reading and checking the file, making the grid again.
  const auto dir =
      std::filesystem::path("/tmp") / ("prt-bench-cache-" + std::to_string(::getpid()));
  BakeOptions cached;
  cached.cache_dir = dir;
  bake_prt(cases[3].mesh, cases[3].scene, cached);
  const Bake hit = bake_prt(cases[3].mesh, cases[3].scene, cached);
  std::printf("pawn on plane from the cache: %s in %.1f ms\n", hit.from_cache() ? "hit" : "MISS",
              1e3 * hit.seconds);
  std::filesystem::remove_all(dir);
  std::printf("load average at end %.2f\n", load_average());
}

}  // namespace
}  // namespace probeless::prt
