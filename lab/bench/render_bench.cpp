#include "lab/bench/render_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <numbers>
#include <vector>

#include "base/stage_stats.hpp"

namespace probeless::render {
namespace {

constexpr double kPi = std::numbers::pi;

// A dim sky over a darker ground with a small bright sun at `azimuth`: what a keyframe of a
// room with one lamp looks like to the materials.
std::shared_ptr<const Environment> sky_with_sun(int face_size, double azimuth) {
  const Eigen::Vector3d sun(std::cos(azimuth) * 0.6, std::sin(azimuth) * 0.6, 0.8);
  Cubemap cube(face_size);
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < face_size; ++y)
      for (int x = 0; x < face_size; ++x) {
        const Eigen::Vector3d d =
            cube_direction(static_cast<CubeFace>(f), (x + 0.5) / face_size, (y + 0.5) / face_size);
        const double s = std::exp(500.0 * (d.dot(sun.normalized()) - 1.0));
        const double sky = d.z() > 0 ? 0.6 + 0.4 * d.z() : 0.25;
        for (int c = 0; c < 3; ++c)
          cube.faces[static_cast<std::size_t>(f)].at(x, y, c) =
              static_cast<float>(sky * (c == 2 ? 1.2 : 1.0) + 200.0 * s);
      }
  return std::make_shared<const Environment>(make_environment(cube));
}

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

void summarise(std::vector<double>& ms, std::vector<double>& cpu, RenderBenchResult& result) {
  result.frames = static_cast<int>(ms.size());
  if (ms.empty()) return;
  std::sort(cpu.begin(), cpu.end());
  result.cpu_p50_ms = cpu[cpu.size() / 2];
  result.cpu_min_ms = cpu.front();
  std::sort(ms.begin(), ms.end());
  auto at = [&](double q) { return ms[static_cast<std::size_t>(q * (ms.size() - 1) + 0.5)]; };
  result.p50_ms = at(0.5);
  result.p90_ms = at(0.9);
  result.max_ms = ms.back();
  result.min_ms = ms.front();
}

}  // namespace

RenderBenchResult bench_render(Renderer& renderer, const PinholeIntrinsics& intrinsics, int frames,
                               const RenderBenchScene& scene) {
  Mesh mesh = make_builtin(scene.shape);
  if (scene.material.shading == Material::Shading::PrtDiffuse) {
    // Clamped cosine of the normal, T_i = A_l Y_i(n) / pi: the cost of PRT does not depend
    // on what the transfer holds.
    constexpr double kA[5] = {kPi, 2 * kPi / 3, kPi / 4, 0, -kPi / 24};
    for (const Eigen::Vector3f& n : mesh.normals) {
      const ShBasis y = sh_basis(n.cast<double>());
      for (int i = 0; i < kShMaxCount; ++i)
        mesh.prt_transfer.push_back(static_cast<float>(kA[static_cast<int>(std::sqrt(i))] *
                                                       y[static_cast<std::size_t>(i)] / kPi));
    }
  }
  VirtualObject object;
  object.mesh = std::make_shared<const Mesh>(std::move(mesh));
  object.material = scene.material;
  if (object.material.shading != Material::Shading::Lambert)
    object.environment = sky_with_sun(scene.face_size, 0.5);
  const Eigen::Vector3f bounds_min = object.mesh->bounds().first;
  const Eigen::Vector3f bounds_max = object.mesh->bounds().second;
  const Eigen::Vector3d target = (0.5f * (bounds_min + bounds_max)).cast<double>();
  const std::vector<VirtualObject> objects{object};
  RenderTarget out;
  out.output = scene.output;
  RenderBenchResult result;
  result.triangles = object.mesh->triangle_count();
  std::vector<double> ms, cpu;
  for (int i = 0; i <= frames; ++i) {  // frame 0 is the cold one, reported apart
    const double a = 2 * kPi * i / std::max(frames, 1);
    const Eigen::Vector3d eye =
        target + Eigen::Vector3d(0.4 * std::cos(a), 0.4 * std::sin(a), 0.16);
    const Camera camera{intrinsics, camera_look_at(eye, target)};
    const double c0 = cpu_ms();
    const auto t0 = std::chrono::steady_clock::now();
    renderer.render(camera, objects, out);
    const double dt = ms_since(t0);
    if (i == 0) {
      result.first_ms = dt;
    } else {
      ms.push_back(dt);
      cpu.push_back(cpu_ms() - c0);
    }
  }
  summarise(ms, cpu, result);
  return result;
}

RenderBenchResult bench_prefilter(Renderer& renderer, int face_size, int updates) {
  // The environments are made before timing: in the service they come from the light
  // estimator, which has its own bench.
  std::vector<std::shared_ptr<const Environment>> envs;
  for (int i = 0; i <= updates; ++i) envs.push_back(sky_with_sun(face_size, 0.2 * i));
  RenderBenchResult result;
  std::vector<double> ms, cpu;
  for (int i = 0; i <= updates; ++i) {
    const double c0 = cpu_ms();
    const auto t0 = std::chrono::steady_clock::now();
    renderer.prepare(envs[static_cast<std::size_t>(i)]);
    renderer.finish();
    const double dt = ms_since(t0);
    if (i == 0) {
      result.first_ms = dt;
    } else {
      ms.push_back(dt);
      cpu.push_back(cpu_ms() - c0);
    }
    if (i > 0) envs[static_cast<std::size_t>(i - 1)].reset();  // as a replaced light would be
  }
  summarise(ms, cpu, result);
  return result;
}

}  // namespace probeless::render
