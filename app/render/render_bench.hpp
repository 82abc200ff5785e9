#pragma once
// Frame time of the renderer on the default scene (the built-in pawn filling about half of
// a 640x480 view, the camera orbiting it), for `probeless bench` and docs/rendering.md.
// Each sample is one whole render(): draw, wait for the rasteriser, read colour and depth.
#include <cstddef>
#include <string>

#include "app/render/renderer.hpp"

namespace probeless::render {

struct RenderBenchResult {
  int frames = 0;
  std::size_t triangles = 0;
  double p50_ms = 0, p90_ms = 0, max_ms = 0;
  double first_ms = 0;  // the first frame: mesh upload and framebuffer set-up included
};

RenderBenchResult bench_render(Renderer& renderer, const PinholeIntrinsics& intrinsics,
                               int frames = 200);

}  // namespace probeless::render
