// probeless bench composite: the first two stages of a frame (Direct matte, composite) on the
// OpenCL device, on a synthetic 640x480 frame by default, and the HDR compositor
// (docs/compositing.md) on the same frame. Every timed region ends with queue.finish(), so the
// numbers are device time as the pipeline sees it, not enqueue time.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <random>

#include "base/stage_stats.hpp"
#include "kernels/composite/compositor.hpp"
#include "kernels/composite/hdr_compositor.hpp"
#include "kernels/occlusion/baselines/direct_matte.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct BenchOptions {
  int width = 640;
  int height = 480;
  int frames = 200;
  int warmup = 20;
  bool direct2 = false;
};

// A frame with the structure of a real one: a noisy wall at 2 m with holes, a box in front
// of part of it, and a virtual disc at 1.5 m in the middle. For the HDR compositor the disc
// also casts a shadow: an ellipse below it on a receiver 5 cm in front of the wall, which the
// virtual depth includes (docs/compositing.md: the matte must cover the shadow too).
struct Frame {
  ImageRGB8 colour;
  DepthImage real;
  ImageF virt;
  ImageRGBA8 virt_rgba;
  ImageF virt_with_receiver;
  Image<float, 4> layer;  // premultiplied radiance + coverage
};

Frame synthetic_frame(int w, int h) {
  Frame f{ImageRGB8(w, h),  DepthImage(w, h), ImageF(w, h),
          ImageRGBA8(w, h), ImageF(w, h),     Image<float, 4>(w, h)};
  std::mt19937 rng(1);
  std::normal_distribution<float> noise(0.0F, 8.0F);
  std::uniform_int_distribution<int> byte(0, 255), hole(0, 49);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool box = x < w / 2 && y > h / 3;
      const float d = (box ? 1200.0F : 2000.0F) + noise(rng);
      f.real.at(x, y) = hole(rng) == 0 ? 0 : static_cast<std::uint16_t>(d);
      const float dx = static_cast<float>(x - w / 2), dy = static_cast<float>(y - h / 2);
      f.virt.at(x, y) = dx * dx + dy * dy < static_cast<float>(h * h) / 9.0F ? 1500.0F : 0.0F;
      for (int c = 0; c < 3; ++c) f.colour.at(x, y, c) = static_cast<std::uint8_t>(byte(rng));
      for (int c = 0; c < 4; ++c) f.virt_rgba.at(x, y, c) = static_cast<std::uint8_t>(byte(rng));
      const bool object = f.virt.at(x, y) > 0.0F;
      const float sy = (dy - static_cast<float>(h) / 4.0F) / (static_cast<float>(h) / 5.0F);
      const float sx = dx / (static_cast<float>(h) / 2.5F);
      const bool shadow = !object && sx * sx + sy * sy < 1.0F;
      f.virt_with_receiver.at(x, y) = object ? 1500.0F : (shadow ? 1950.0F : 0.0F);
      float* l = &f.layer.at(x, y, 0);
      for (int c = 0; c < 3; ++c)
        l[c] = object ? 0.2F + 0.1F * static_cast<float>(c) : (shadow ? -0.05F : 0.0F);
      l[3] = object ? 1.0F : 0.0F;
    }
  return f;
}

struct Timing {
  TimingSummary wall;
  double cpu_ms_per_frame = 0;  // the process's CPU time (all threads): steadier under load
};

Timing time_frames(ComputeContext& ctx, const BenchOptions& o, const std::function<void()>& frame) {
  for (int i = 0; i < o.warmup; ++i) frame();
  ctx.queue().finish();
  std::vector<double> samples;
  samples.reserve(static_cast<std::size_t>(o.frames));
  const double cpu0 = process_cpu_ms();
  for (int i = 0; i < o.frames; ++i) {
    const auto t0 = Clock::now();
    frame();
    ctx.queue().finish();
    samples.push_back(ms_since(t0));
  }
  const double cpu = (process_cpu_ms() - cpu0) / o.frames;
  return {summarize(std::move(samples)), cpu};
}

void print_row(const std::string& label, const Timing& t) {
  const auto& s = t.wall;
  std::cout << fmt::format(
      "  {:<36} p50 {:7.3f} ms  p99 {:7.3f} ms  mean {:7.3f} ms  cpu {:7.3f} ms/frame\n", label,
      s.p50_ms, s.p99_ms, s.mean_ms, t.cpu_ms_per_frame);
}

void run(const BenchOptions& o) {
  const auto t_start = Clock::now();
  ComputeContext ctx;
  const double context_ms = ms_since(t_start);
  const auto t_programs = Clock::now();
  occlusion::DirectMatte direct(
      ctx, o.direct2 ? occlusion::UnknownDepth::Visible : occlusion::UnknownDepth::Occluded);
  Compositor compositor(ctx);
  HdrCompositor hdr(ctx);
  const double programs_ms = ms_since(t_programs);
  const auto cache = ctx.cache_stats();

  const auto host = synthetic_frame(o.width, o.height);
  DeviceImageRGB8 colour(ctx, host.colour), out;
  DeviceDepthImage real(ctx, host.real);
  DeviceImageF virt(ctx, host.virt), alpha;
  DeviceImageRGBA8 virt_rgba(ctx, host.virt_rgba);
  const occlusion::OcclusionInputs in{&colour, &real, &virt};
  ImageRGB8 result;

  std::cout << fmt::format("bench composite: {} + composite, {}x{}, {} frames ({} warm-up)\n",
                           direct.name(), o.width, o.height, o.frames, o.warmup);
  std::cout << fmt::format("  device: {}\n", ctx.describe());
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) == 3)
    std::cout << fmt::format("  load average: {:.2f} {:.2f} {:.2f}\n", load[0], load[1], load[2]);
  std::cout << fmt::format(
      "  start-up: context {:.1f} ms, programs {:.1f} ms ({} from the disk cache, {} compiled; "
      "cache {})\n",
      context_ms, programs_ms, cache.disk_hits, cache.source_builds,
      ctx.cache_dir().empty() ? "off" : ctx.cache_dir().string());
  print_row("direct + composite (device)", time_frames(ctx, o, [&] {
              direct.process(in, alpha);
              compositor.process(colour, virt_rgba, alpha, out);
            }));
  print_row("direct only", time_frames(ctx, o, [&] { direct.process(in, alpha); }));
  print_row("composite only",
            time_frames(ctx, o, [&] { compositor.process(colour, virt_rgba, alpha, out); }));
  print_row("upload 4 inputs + both + download", time_frames(ctx, o, [&] {
              colour.upload(ctx.queue(), host.colour, false);
              real.upload(ctx.queue(), host.real, false);
              virt.upload(ctx.queue(), host.virt, false);
              virt_rgba.upload(ctx.queue(), host.virt_rgba, false);
              direct.process(in, alpha);
              compositor.process(colour, virt_rgba, alpha, out);
              out.download(ctx.queue(), result);
            }));

  // HDR compositing: the matte of the object and its shadow's receiver, computed once.
  DeviceImageF virt_with_receiver(ctx, host.virt_with_receiver), hdr_alpha;
  DeviceImage<float, 4> layer(ctx, host.layer);
  direct.process({&colour, &real, &virt_with_receiver}, hdr_alpha);
  const ImageF hdr_alpha_host = hdr_alpha.download(ctx.queue());
  std::size_t covered = 0;
  for (const float a : hdr_alpha_host.elements()) covered += a > 0.0F;
  const CameraResponse camera{{0.8, 1.0, 1.3}, 2.2};
  std::cout << fmt::format(
      "  hdr composite: matte > 0 on {:.1f} % of the frame (object + shadow receiver)\n",
      100.0 * static_cast<double>(covered) / static_cast<double>(hdr_alpha_host.pixel_count()));
  print_row("hdr composite only",
            time_frames(ctx, o, [&] { hdr.process(colour, layer, hdr_alpha, camera, out); }));
  DeviceImageF nowhere(ctx, ImageF(o.width, o.height, 0.0F));
  print_row("hdr composite, matte 0 (the copy)",
            time_frames(ctx, o, [&] { hdr.process(colour, layer, nowhere, camera, out); }));
  DeviceImageF everywhere(ctx, ImageF(o.width, o.height, 0.7F));
  print_row("hdr composite, matte 0.7 everywhere",
            time_frames(ctx, o, [&] { hdr.process(colour, layer, everywhere, camera, out); }));
  print_row("direct + hdr composite (device)", time_frames(ctx, o, [&] {
              direct.process({&colour, &real, &virt_with_receiver}, hdr_alpha);
              hdr.process(colour, layer, hdr_alpha, camera, out);
            }));
}

}  // namespace

void add_bench_composite_command(CLI::App& bench) {
  auto o = std::make_shared<BenchOptions>();
  auto* cmd = bench.add_subcommand("composite",
                                   "Direct matte + composite (8-bit and HDR) on the OpenCL device");
  cmd->add_option("--width", o->width, "Frame width")->check(CLI::Range(1, 8192));
  cmd->add_option("--height", o->height, "Frame height")->check(CLI::Range(1, 8192));
  cmd->add_option("--frames", o->frames, "Timed frames per row")->check(CLI::Range(1, 100000));
  cmd->add_option("--warmup", o->warmup, "Untimed frames first")->check(CLI::Range(0, 10000));
  cmd->add_flag("--direct2", o->direct2, "Unknown depth visible (Direct2) instead of Direct1");
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli
