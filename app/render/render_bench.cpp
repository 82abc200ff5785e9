#include "app/render/render_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

namespace probeless::render {

RenderBenchResult bench_render(Renderer& renderer, const PinholeIntrinsics& intrinsics,
                               int frames) {
  VirtualObject pawn;
  pawn.mesh = std::make_shared<const Mesh>(make_pawn(0.2f));
  pawn.material.base_colour = {0.75f, 0.18f, 0.12f, 1.f};
  const std::vector<VirtualObject> scene{pawn};
  RenderTarget out;
  RenderBenchResult result;
  result.triangles = pawn.mesh->triangle_count();
  std::vector<double> ms;
  for (int i = 0; i <= frames; ++i) {  // frame 0 is the cold one, reported apart
    const double a = 2 * std::numbers::pi * i / std::max(frames, 1);
    const Camera camera{intrinsics,
                        camera_look_at({0.4 * std::cos(a), 0.4 * std::sin(a), 0.25}, {0, 0, 0.09})};
    const auto t0 = std::chrono::steady_clock::now();
    renderer.render(camera, scene, out);
    const auto t1 = std::chrono::steady_clock::now();
    const double dt = std::chrono::duration<double, std::milli>(t1 - t0).count();
    if (i == 0)
      result.first_ms = dt;
    else
      ms.push_back(dt);
  }
  result.frames = static_cast<int>(ms.size());
  if (ms.empty()) return result;
  std::sort(ms.begin(), ms.end());
  auto at = [&](double q) { return ms[static_cast<std::size_t>(q * (ms.size() - 1) + 0.5)]; };
  result.p50_ms = at(0.5);
  result.p90_ms = at(0.9);
  result.max_ms = ms.back();
  return result;
}

}  // namespace probeless::render
