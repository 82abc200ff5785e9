#include "kernels/envmap/envmap_update.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "kernels/envmap/envmap_update_cl.hpp"
#include "kernels/hdr/hdr_conversion_cl.hpp"

namespace probeless::envmap {

namespace {

// The update program is the HDR conversion's source followed by the update's: the fused
// kernel calls the conversion's convert_one, so the two can never disagree about a pixel.
std::string program_source() {
  std::string s(cl_source::hdr_conversion);
  s += '\n';
  s += cl_source::envmap_update;
  return s;
}

cl_float4 float4_of(const Eigen::Vector3f& v) {
  return cl_float4{{v.x(), v.y(), v.z(), 0.0F}};
}

constexpr int kLanes = 16;  // texels per work-item (envmap_update.cl)

// One work-item per 16 texels of a row: 8 x 8 work-items (a 128 x 8 block of a 128 px face)
// per group.
void launch(ComputeContext& ctx, const ::cl::Kernel& kernel, int n) {
  const std::size_t items = static_cast<std::size_t>((n + kLanes - 1) / kLanes);
  const std::size_t max = ctx.local_2d()[0] * ctx.local_2d()[1];
  const std::size_t lx = std::min<std::size_t>({8, items, max});
  const std::size_t ly = std::max<std::size_t>(1, std::min<std::size_t>(8, max / lx));
  ctx.queue().enqueueNDRangeKernel(
      kernel, ::cl::NullRange,
      ::cl::NDRange(round_up(items, lx), round_up(static_cast<std::size_t>(6 * n), ly)),
      ::cl::NDRange(lx, ly));
}

}  // namespace

EnvmapUpdate::EnvmapUpdate(ComputeContext& ctx, const UpdateParams& params,
                           const HdrConversionParams& hdr)
    : ctx_(ctx), params_(params), hdr_(hdr) {
  validate(hdr_);
  const std::string source = program_source();
  converted_ = ctx.kernel("envmap_update", source, {}, "envmap_update");
  raw_ = ctx.kernel("envmap_update", source, {}, "envmap_update_raw");
}

// A frame of another size than the camera the table was built from would be sampled at the
// wrong pixels without any error showing: refuse it, naming both.
void EnvmapUpdate::check_frame(const FisheyeView& view, int width, int height) {
  if (view.lut && (view.lut->image_width != width || view.lut->image_height != height))
    throw std::invalid_argument(
        "the fisheye source's frames are " + std::to_string(width) + " x " +
        std::to_string(height) + ", but the calibration's fisheye (" + view.lut->model + ") is " +
        std::to_string(view.lut->image_width) + " x " + std::to_string(view.lut->image_height) +
        " (calibrate at the size the camera runs at, or set its size= to the calibration's)");
}

void EnvmapUpdate::check(const DeviceImage<float, 4>& texels,
                         const DeviceImage<float, 4>& pending) {
  if (texels.height() != 6 * texels.width())
    throw std::invalid_argument("EnvmapUpdate: texels must be n x 6n");
  if (!pending.same_size(texels))
    throw std::invalid_argument("EnvmapUpdate: pending must match texels");
}

// The camera's table on the device: uploaded when the view brings a different one (once per
// estimator in the service, whose fisheye never changes).
const ::cl::Buffer& EnvmapUpdate::device_lut(const FisheyeView& view) {
  if (!view.lut || view.lut->size < 2)
    throw std::invalid_argument("EnvmapUpdate: the view has no fisheye table");
  if (view.lut != lut_) {
    lut_device_.upload(ctx_.queue(), view.lut->pixel);
    lut_ = view.lut;
  }
  return lut_device_.buffer();
}

// The cosine below which a group of texels is out of the fisheye's table (envmap_update.cl,
// group_hidden): the table's max_theta, widened under parallax by the most the wall point can
// be off the texel's direction as the fisheye sees it (the fisheye is |offset| from the
// keyframe, every wall at least the nearest wall's distance away: asin(|offset| / that)), and
// by 1e-3 rad for float rounding. -2 (never) when that reaches pi.
float EnvmapUpdate::cull_cos(const FisheyeView& view, const ParallaxConstants& p) {
  double limit = view.lut->max_theta + 1e-3;
  if (p.enabled) {
    const float nearest_wall = std::min((-p.lo).minCoeff(), p.hi.minCoeff());
    const float off = p.offset.norm();
    limit = off < nearest_wall ? limit + std::asin(off / nearest_wall) : 10.0;
  }
  return limit < M_PI ? static_cast<float>(std::cos(limit)) : -2.0F;
}

void EnvmapUpdate::set_view_args(::cl::Kernel& kernel, int a, int n, const FisheyeView& view,
                                 bool publish) {
  const Eigen::Matrix3f r = view.R_camera_world.cast<float>();
  const auto row = [&](int i) { return cl_float4{{r(i, 0), r(i, 1), r(i, 2), 0.0F}}; };
  const ParallaxConstants p = parallax_constants(view);
  const float sigma2 = params_.measurement_sigma * params_.measurement_sigma;
  const float process2 = params_.process_sigma * params_.process_sigma;
  const float change2 =
      params_.change_sigma > 0 ? params_.change_sigma * params_.change_sigma : 0.0F;
  kernel.setArg(a++, n);
  kernel.setArg(a++, row(0));
  kernel.setArg(a++, row(1));
  kernel.setArg(a++, row(2));
  kernel.setArg(a++, device_lut(view));
  kernel.setArg(a++, view.lut->size);
  kernel.setArg(a++, view.lut->centre);
  kernel.setArg(a++, view.lut->scale);
  kernel.setArg(a++, view.lut->max_theta);
  kernel.setArg(a++, p.enabled ? 1 : 0);
  kernel.setArg(a++, float4_of(p.lo));
  kernel.setArg(a++, float4_of(p.hi));
  kernel.setArg(a++, float4_of(p.offset));
  kernel.setArg(a++, params_.rule == UpdateRule::Kalman ? 0 : 1);
  kernel.setArg(a++, publish ? 1 : 0);
  kernel.setArg(a++, sigma2);
  kernel.setArg(a++, process2);
  kernel.setArg(a++, change2);
  kernel.setArg(a++, cull_cos(view, p));
}

void EnvmapUpdate::update(const DeviceImage<float, 4>& image, const FisheyeView& view, bool publish,
                          DeviceImage<float, 4>& texels, DeviceImage<float, 4>& pending) {
  check(texels, pending);
  if (texels.empty() || image.empty()) return;
  check_frame(view, image.width(), image.height());
  const int n = texels.width();
  int a = 0;
  converted_.setArg(a++, texels.buffer());
  converted_.setArg(a++, pending.buffer());
  converted_.setArg(a++, image.buffer());
  converted_.setArg(a++, image.width());
  converted_.setArg(a++, image.height());
  set_view_args(converted_, a, n, view, publish);
  launch(ctx_, converted_, n);
}

void EnvmapUpdate::update_raw(const DeviceImage<std::uint16_t, 3>& raw, int bit_depth,
                              std::uint16_t black_level, const Exposure& exposure,
                              const FisheyeView& view, bool publish, DeviceImage<float, 4>& texels,
                              DeviceImage<float, 4>& pending) {
  check(texels, pending);
  const HdrConversionConstants c = hdr_conversion_constants(bit_depth, black_level, exposure, hdr_);
  if (texels.empty() || raw.empty()) return;
  check_frame(view, raw.width(), raw.height());
  const int n = texels.width();
  int a = 0;
  raw_.setArg(a++, texels.buffer());
  raw_.setArg(a++, pending.buffer());
  raw_.setArg(a++, raw.buffer());
  raw_.setArg(a++, raw.width());
  raw_.setArg(a++, raw.height());
  raw_.setArg(a++, static_cast<int>(black_level));
  raw_.setArg(a++, c.saturated_signal);
  raw_.setArg(a++, c.black_margin);
  raw_.setArg(a++, c.radiance_scale);
  raw_.setArg(a++, c.inv_range);
  raw_.setArg(a++, c.crop ? 1 : 0);
  raw_.setArg(a++, c.circle_cx);
  raw_.setArg(a++, c.circle_cy);
  raw_.setArg(a++, c.circle_radius2);
  set_view_args(raw_, a, n, view, publish);
  launch(ctx_, raw_, n);
}

}  // namespace probeless::envmap
