#pragma once
// Frame time of the renderer (docs/rendering.md "Speed", docs/performance.md): the default
// scene (the built-in pawn filling about half of a 640x480 view, the camera orbiting it) in
// any material, and the environment upload + prefilter of a light update. Each frame sample
// is one whole render(): draw, wait for the rasteriser, read colour and depth.
#include <cstddef>
#include <string>

#include "app/render/renderer.hpp"

namespace probeless::render {

struct RenderBenchResult {
  int frames = 0;
  std::size_t triangles = 0;
  double p50_ms = 0, p90_ms = 0, max_ms = 0, min_ms = 0;
  double first_ms = 0;  // the first frame: mesh upload, shader compilation, set-up included
  // The process's CPU time per sample (all threads: llvmpipe rasterises on its own), which
  // a loaded machine inflates far less than wall time.
  double cpu_p50_ms = 0, cpu_min_ms = 0;
};

struct RenderBenchScene {
  std::string shape = "pawn";  // make_builtin()'s name
  Material material;           // base colour: the pawn's red unless set
  // The image-based materials' light: a sky with a sun, face_size px faces (the light
  // estimator's keyframes are 128); PRT gets clamped-cosine transfer (no shadows).
  int face_size = 128;
  ColourOutput output = ColourOutput::Display8;
};

RenderBenchResult bench_render(Renderer& renderer, const PinholeIntrinsics& intrinsics,
                               int frames = 200, const RenderBenchScene& scene = {});

// One light update as the renderer sees it: a new Environment (a sky whose sun moves between
// updates) uploaded and prefiltered, waiting for the GPU. first_ms includes compiling the
// prefilter program.
RenderBenchResult bench_prefilter(Renderer& renderer, int face_size, int updates = 30);

}  // namespace probeless::render
