#include "kernels/fusion/surfel_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kernels/fusion/surfel_map_cl.hpp"
#include "kernels/occlusion/common/vector16_cl.hpp"

namespace probeless::fusion {
namespace {

constexpr std::size_t kFloatPlanes = SurfelPlanes::kPlanes;  // surfel_map.cl's FLOAT_PLANES
static_assert(kFloatPlanes == 11);
// Surfels a work-item of the compaction and the keep rules walks in order: 256 keeps the scan
// over blocks short (~90 blocks for the sim's 23 000 surfels) and gives each of PoCL's
// workers several blocks.
constexpr int kBlock = 256;
constexpr std::size_t kLocal1d = 64;   // per-surfel kernels (scalar: the atomic, the branches)
constexpr std::size_t kLocalWalk = 4;  // per-row and per-block walks: spread over the workers
constexpr int kHistogramChunk = 4096;  // surfels per work-item of the eviction's histogram
constexpr std::size_t kMinCapacity = 4096;
constexpr std::size_t kMaxCapacity = std::size_t{1} << 24;  // the eviction key's 24-bit index

// surfel_map.cl's Frame, field for field (48 four-byte fields).
struct FrameArg {
  std::array<cl_float, 9> r_cw;
  std::array<cl_float, 3> t_cw;
  std::array<cl_float, 9> r_wc;
  std::array<cl_float, 3> t_wc;
  cl_float fx, fy, cx, cy, f_mean;
  cl_float inv_max_radius_factor, region_r2;
  std::array<cl_float, 3> region;
  cl_float depth_tolerance, cos_normal, violation_margin, discontinuity;
  cl_float min_depth, max_depth, clipped_scale;
  std::array<cl_float, 3> radiance_per_unit;
  cl_int width, height, saturated_level, black_level;
};
static_assert(sizeof(FrameArg) == 48 * 4);

const std::string& surfel_map_source() {
  static const std::string source =
      std::string(cl_source::vector16) + std::string(cl_source::surfel_map);
  return source;
}

// A launch over `r` in blocks of 16 pixels of a row (surfel_map.cl's row-streaming kernels),
// the work-group left to PoCL: an explicit (1, 8) cost 40-43 CPU-ms a VGA frame against 28-29
// (interleaved A/B, docs/fusion.md "The surfel map on the device").
void run_rows_of_16(ComputeContext& ctx, const ::cl::Kernel& kernel, const PixelRect& r) {
  if (r.empty()) return;
  ctx.queue().enqueueNDRangeKernel(kernel, ::cl::NullRange,
                                   ::cl::NDRange(static_cast<std::size_t>((r.width() + 15) / 16),
                                                 static_cast<std::size_t>(r.height())),
                                   ::cl::NullRange);
}

cl_int4 rect_arg(const PixelRect& r) {
  return {{r.x0, r.y0, r.x1, r.y1}};
}

template <typename... Args>
void set_args(::cl::Kernel& kernel, const Args&... args) {
  cl_uint i = 0;
  (kernel.setArg(i++, args), ...);
}

// The pixels whose world point can lie in the region's sphere: the bounding box of its
// projection (per axis the two planes through the camera's centre tangent to it), 2 px wider
// for rounding; the whole image when the camera is not clear of the sphere in front.
PixelRect region_rect(const FrameArg& f, const Eigen::Vector3f& centre, float radius) {
  const PixelRect whole = PixelRect::whole(f.width, f.height);
  double c[3];
  for (int r = 0; r < 3; ++r)
    c[r] = double{f.r_cw[3 * r]} * centre.x() + double{f.r_cw[3 * r + 1]} * centre.y() +
           double{f.r_cw[3 * r + 2]} * centre.z() + f.t_cw[r];
  const double cz = c[2], r2 = double{radius} * radius, a = cz * cz - r2;
  if (!(cz > 0) || !(a > 1e-6 * r2)) return whole;
  // The planes x = t z tangent to the sphere: (c_x - t c_z)^2 = r^2 (1 + t^2).
  const auto span = [&](double cx, double focal, double principal) {
    const double root = std::sqrt(std::max(0.0, cx * cx + a)) * radius;
    const double t0 = (cx * cz - root) / a, t1 = (cx * cz + root) / a;
    return std::array<double, 2>{focal * t0 + principal, focal * t1 + principal};
  };
  const auto u = span(c[0], f.fx, f.cx), v = span(c[1], f.fy, f.cy);
  const auto clampi = [](double x) { return static_cast<int>(std::clamp(x, -1e6, 1e6)); };
  return intersect({clampi(std::floor(u[0])) - 2, clampi(std::floor(v[0])) - 2,
                    clampi(std::ceil(u[1])) + 3, clampi(std::ceil(v[1])) + 3},
                   whole);
}

}  // namespace

SurfelMapDevice::SurfelMapDevice(ComputeContext& ctx, SurfelMapParams params)
    : ctx_(ctx), params_(params) {
  check_surfel_map_params(params_, "SurfelMapDevice");
  const auto extensions = ctx.device().getInfo<CL_DEVICE_EXTENSIONS>();
  if (extensions.find("cl_khr_int64_extended_atomics") == std::string::npos)
    throw std::runtime_error(
        "SurfelMapDevice: the device has no cl_khr_int64_extended_atomics (the index map's "
        "nearest-wins atom_min)");
  // Division and sqrt correctly rounded, as on the host: the device takes the reference's
  // decisions (thresholds on depths, normals and confidences) unless a table says otherwise.
  const std::string options = fmt::format(
      "-DINDEX_SCALE={} -DNORMAL_STEP={} -DSMOOTH_R={} -DPAD={} -DBLOCK={} "
      "-cl-fp32-correctly-rounded-divide-sqrt",
      params_.index_scale, params_.normal_step_px, params_.normal_smoothing_px, pad(), kBlock);
  const auto make = [&](const char* name) {
    return ctx.kernel("surfel_map", surfel_map_source(), options, name);
  };
  clear_ = make("clear_index_map");
  project_ = make("project_surfels");
  mask_ = make("prepare_depth");
  smooth_ = make("smooth_depth");
  fuse_ = make("fuse_pixels");
  count_rows_ = make("count_row_codes");
  keep_rule_ = make("keep_frame_rule");
  scan_ = make("scan_counts");
  compact_ = make("compact_surfels");
  births_ = make("write_births");
  histogram_ = make("eviction_histogram");
  select_ = make("eviction_select");
  keep_below_ = make("keep_below_key");

  std::array<cl_float, 256> linear{};
  for (int v = 0; v < 256; ++v)
    linear[static_cast<std::size_t>(v)] = static_cast<float>(std::pow(v / 255.0, params_.gamma));
  linear_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(linear),
                         linear.data());
  totals_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, 8 * sizeof(cl_uint));
  histogram_buf_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, 256 * sizeof(cl_uint));
  select_state_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, 8 * sizeof(cl_uint));
  ctx.queue().enqueueFillBuffer(histogram_buf_, cl_uint{0}, 0, 256 * sizeof(cl_uint));
}

void SurfelMapDevice::run_1d(const ::cl::Kernel& kernel, std::size_t items, std::size_t local) {
  if (items == 0) return;
  ctx_.queue().enqueueNDRangeKernel(kernel, ::cl::NullRange, ::cl::NDRange(round_up(items, local)),
                                    ::cl::NDRange(local));
}

void SurfelMapDevice::prepare_frame_buffers(const PinholeIntrinsics& k) {
  const auto& c = ctx_.context();
  auto& q = ctx_.queue();
  const std::size_t pixels = static_cast<std::size_t>(k.width) * k.height;
  if (k.width != width_ || k.height != height_) {
    const std::size_t cells = pixels * params_.index_scale * params_.index_scale;
    index_map_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, cells * sizeof(cl_ulong));
    q.enqueueFillBuffer(index_map_, ~cl_ulong{0}, 0, cells * sizeof(cl_ulong));
    projected_ = 0;  // nothing of the old map to clear
    // + a vector: fuse_pixels loads 16 pixels from the rectangle's last column.
    smoothed_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, (pixels + 16) * sizeof(cl_float));
    nearest3_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, pixels * sizeof(cl_float));
    // The smoothing's input, padded by its radius in zeros (written once: the kernel writes
    // only the image's pixels).
    const int pad = this->pad();
    // + a vector and the window's reach: the last row's last block reads past its end.
    const std::size_t padded =
        static_cast<std::size_t>(k.width + 2 * pad) * static_cast<std::size_t>(k.height + 2 * pad) +
        16 + 2 * pad;
    padded_depth_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, padded * sizeof(cl_float));
    q.enqueueFillBuffer(padded_depth_, cl_float{0}, 0, padded * sizeof(cl_float));
    mask_buf_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, pixels);
    codes_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, pixels);
    radial_weight_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, pixels * sizeof(cl_float));
    fused_rows_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, static_cast<std::size_t>(k.height) * 4);
    born_rows_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, static_cast<std::size_t>(k.height) * 4);
    width_ = k.width;
    height_ = k.height;
    weight_cx_ = NAN;
  }
  const auto cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
  if (!(cx == weight_cx_ && cy == weight_cy_)) {
    // The reference's expressions, with its std:: functions: the weights are bit for bit its.
    std::vector<float> weight(pixels);
    const float half_diagonal =
        0.5f * std::hypot(static_cast<float>(k.width), static_cast<float>(k.height));
    const float sigma = params_.radial_sigma;
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) {
        const float g =
            std::hypot(static_cast<float>(x) - cx, static_cast<float>(y) - cy) / half_diagonal;
        weight[static_cast<std::size_t>(y) * k.width + x] = std::exp(-g * g / (2 * sigma * sigma));
      }
    q.enqueueWriteBuffer(radial_weight_, CL_TRUE, 0, pixels * sizeof(float), weight.data());
    weight_cx_ = cx;
    weight_cy_ = cy;
  }
}

void SurfelMapDevice::ensure_capacity(std::size_t needed) {
  if (needed <= sets_[current_].capacity && sets_[current_].capacity > 0) return;
  if (needed > kMaxCapacity)
    throw std::runtime_error(
        fmt::format("SurfelMapDevice: {} surfels and births exceed the map's limit of {}", needed,
                    kMaxCapacity));
  const std::size_t cap =
      std::min(kMaxCapacity, std::max({needed, 2 * sets_[current_].capacity, kMinCapacity}));
  const auto& c = ctx_.context();
  auto& q = ctx_.queue();
  const SurfelSet& old = sets_[current_];
  SurfelSet grown{::cl::Buffer(c, CL_MEM_READ_WRITE, kFloatPlanes * cap * sizeof(cl_float)),
                  ::cl::Buffer(c, CL_MEM_READ_WRITE, 2 * cap * sizeof(cl_long)),
                  ::cl::Buffer(c, CL_MEM_READ_WRITE, cap), cap};
  if (count_ > 0) {  // the map itself, plane by plane to the new stride
    for (std::size_t p = 0; p < kFloatPlanes; ++p)
      q.enqueueCopyBuffer(old.floats, grown.floats, p * old.capacity * sizeof(cl_float),
                          p * cap * sizeof(cl_float), count_ * sizeof(cl_float));
    for (std::size_t p = 0; p < 2; ++p)
      q.enqueueCopyBuffer(old.frames, grown.frames, p * old.capacity * sizeof(cl_long),
                          p * cap * sizeof(cl_long), count_ * sizeof(cl_long));
    q.enqueueCopyBuffer(old.flags, grown.flags, 0, 0, count_);
  }
  ::cl::Buffer cells(c, CL_MEM_READ_WRITE, cap * sizeof(cl_uint));
  if (projected_ > 0) q.enqueueCopyBuffer(cells_, cells, 0, 0, projected_ * sizeof(cl_uint));
  cells_ = cells;
  sets_[current_] = grown;
  sets_[1 - current_] = {::cl::Buffer(c, CL_MEM_READ_WRITE, kFloatPlanes * cap * sizeof(cl_float)),
                         ::cl::Buffer(c, CL_MEM_READ_WRITE, 2 * cap * sizeof(cl_long)),
                         ::cl::Buffer(c, CL_MEM_READ_WRITE, cap), cap};
  violated_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, cap);
  keep_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, cap);
  const std::size_t blocks = (cap + kBlock - 1) / kBlock;
  block_kept_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, blocks * sizeof(cl_uint));
  block_violated_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, blocks * sizeof(cl_uint));
  block_stale_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, blocks * sizeof(cl_uint));
}

SurfelIntegrationStats SurfelMapDevice::integrate(const DepthImage& depth, const ImageRGB8& colour,
                                                  const std::array<float, 3>& radiance_per_unit,
                                                  const PinholeIntrinsics& k,
                                                  const Pose& T_world_camera,
                                                  std::int64_t frame_index) {
  check_surfel_frame("SurfelMapDevice", depth.width(), depth.height(), colour.width(),
                     colour.height(), radiance_per_unit, k);
  // Read in place: integrate() waits for the frame's counts, so the images outlive every
  // command that reads them.
  const auto d = DeviceDepthImage::wrap_host(ctx_.context(), depth);
  const auto c = DeviceImageRGB8::wrap_host(ctx_.context(), colour);
  return integrate(d, c, radiance_per_unit, k, T_world_camera, frame_index);
}

SurfelIntegrationStats SurfelMapDevice::integrate(const DeviceDepthImage& depth,
                                                  const DeviceImageRGB8& colour,
                                                  const std::array<float, 3>& radiance_per_unit,
                                                  const PinholeIntrinsics& k,
                                                  const Pose& T_world_camera,
                                                  std::int64_t frame_index) {
  check_surfel_frame("SurfelMapDevice", depth.width(), depth.height(), colour.width(),
                     colour.height(), radiance_per_unit, k);
  const SurfelMapParams& p = params_;
  prepare_frame_buffers(k);

  // The reference's camera, in floats, both ways.
  const Eigen::Matrix3f R_wc = T_world_camera.rotation.toRotationMatrix().cast<float>();
  const Eigen::Vector3f t_wc = T_world_camera.translation.cast<float>();
  const Eigen::Matrix3f R_cw = R_wc.transpose();
  const Eigen::Vector3f t_cw = -(R_cw * t_wc);
  FrameArg f{};
  for (int i = 0; i < 9; ++i) {
    f.r_cw[static_cast<std::size_t>(i)] = R_cw(i / 3, i % 3);
    f.r_wc[static_cast<std::size_t>(i)] = R_wc(i / 3, i % 3);
  }
  for (int i = 0; i < 3; ++i) {
    const auto j = static_cast<std::size_t>(i);
    f.t_cw[j] = t_cw[i];
    f.t_wc[j] = t_wc[i];
    f.region[j] = p.region_centre[i];
    f.radiance_per_unit[j] = radiance_per_unit[j];
  }
  f.fx = static_cast<float>(k.fx);
  f.fy = static_cast<float>(k.fy);
  f.cx = static_cast<float>(k.cx);
  f.cy = static_cast<float>(k.cy);
  f.f_mean = 0.5f * (f.fx + f.fy);
  f.inv_max_radius_factor = 1.0f / p.max_radius_factor;
  f.region_r2 = p.region_radius_m * p.region_radius_m;
  f.depth_tolerance = p.depth_tolerance_m;
  f.cos_normal = std::cos(p.normal_tolerance_rad);
  f.violation_margin = p.violation_margin_m;
  f.discontinuity = p.discontinuity_ratio;
  f.min_depth = p.min_depth_m;
  f.max_depth = p.max_depth_m;
  f.clipped_scale = p.clipped_weight_scale;
  f.width = k.width;
  f.height = k.height;
  f.saturated_level = p.saturated_level;
  f.black_level = p.black_level;

  // The pixels that can be candidates: the region's projection inside the normal stencil's
  // border; `area` adds the stencil's reach, where the smoothed depth is needed, and `outer`
  // the smoothing's, where the depth is.
  const int step = p.normal_step_px;
  const PixelRect rect = intersect(region_rect(f, p.region_centre, p.region_radius_m),
                                   {step, step, k.width - step, k.height - step});
  const PixelRect area = grown(rect, step, k.width, k.height);
  const PixelRect outer = grown(area, pad(), k.width, k.height);
  const int padded_width = k.width + 2 * pad();
  const auto rect_pixels = static_cast<std::size_t>(rect.width()) * rect.height();
  ensure_capacity(count_ + rect_pixels);
  SurfelSet& cur = sets_[current_];
  SurfelSet& next = sets_[1 - current_];
  const auto cap = static_cast<cl_int>(cur.capacity);
  const auto n = static_cast<cl_int>(count_);
  const auto frame = static_cast<cl_long>(frame_index);

  // The depth first (the padded copy, the mask, the smoothing, the nearest depth around each
  // pixel), then the index map, which the violation test reads it for.
  const auto rows = static_cast<cl_int>(rect.height());
  if (!rect.empty()) {
    set_args(mask_, depth.buffer(), f, rect_arg(rect), rect_arg(outer), padded_width, padded_depth_,
             mask_buf_);
    run_rows_of_16(ctx_, mask_, outer);
    set_args(smooth_, padded_depth_, padded_width, f.width, rect_arg(area), f.discontinuity,
             smoothed_, nearest3_);
    run_rows_of_16(ctx_, smooth_, area);
  }
  set_args(clear_, index_map_, cells_, static_cast<cl_int>(projected_));
  run_1d(clear_, projected_, kLocal1d);
  set_args(project_, cur.floats, cap, n, depth.buffer(), nearest3_, rect_arg(area), f, index_map_,
           cells_, violated_);
  run_1d(project_, count_, kLocal1d);
  projected_ = count_;

  if (!rect.empty()) {
    set_args(fuse_, depth.buffer(), colour.buffer(), smoothed_, radial_weight_, linear_, mask_buf_,
             index_map_, f, rect_arg(rect), frame, cur.floats, cur.frames, cap, codes_);
    run_rows_of_16(ctx_, fuse_, rect);
    set_args(count_rows_, codes_, f.width, rect_arg(rect), fused_rows_, born_rows_);
    run_1d(count_rows_, static_cast<std::size_t>(rows), kLocalWalk);
  }
  const std::size_t blocks = (count_ + kBlock - 1) / kBlock;
  set_args(keep_rule_, cur.floats, cur.frames, cap, n, violated_, p.stable_confidence,
           static_cast<cl_long>(p.unstable_max_unseen_frames), frame, keep_, block_kept_,
           block_violated_, block_stale_);
  run_1d(keep_rule_, blocks, kLocalWalk);
  set_args(scan_, block_kept_, block_violated_, block_stale_, static_cast<cl_int>(blocks),
           fused_rows_, born_rows_, rows, totals_);
  run_1d(scan_, 1, 1);
  const auto next_cap = static_cast<cl_int>(next.capacity);
  set_args(compact_, cur.floats, cur.frames, cur.flags, cap, n, keep_, block_kept_, next.floats,
           next.frames, next.flags, next_cap);
  run_1d(compact_, blocks, kLocalWalk);
  if (!rect.empty()) {
    set_args(births_, depth.buffer(), colour.buffer(), smoothed_, radial_weight_, linear_, codes_,
             f, rect_arg(rect), born_rows_, frame, next.floats, next.frames, next.flags, next_cap);
    run_1d(births_, static_cast<std::size_t>(rows), kLocalWalk);
  }
  std::array<cl_uint, 5> totals{};
  ctx_.queue().enqueueReadBuffer(totals_, CL_TRUE, 0, sizeof(totals), totals.data());
  current_ = 1 - current_;
  count_ = std::size_t{totals[0]} + totals[1];

  SurfelIntegrationStats stats;
  stats.born = totals[1];
  stats.fused = totals[2];
  stats.candidates = stats.born + stats.fused;
  stats.removed_violation = totals[3];
  stats.removed_unstable = totals[4];
  if (count_ > p.max_surfels) {
    stats.evicted = count_ - p.max_surfels;
    evict(stats.evicted);
  }
  return stats;
}

// The budget (issue #21 item 1): the `excess` surfels first in the reference's total order
// (farthest shell, least confident, newest) go. A radix select finds the excess-th key, 8 bits
// a pass, on the device; the compaction keeps the rest in order.
void SurfelMapDevice::evict(std::size_t excess) {
  auto& q = ctx_.queue();
  SurfelSet& cur = sets_[current_];
  SurfelSet& next = sets_[1 - current_];
  const auto cap = static_cast<cl_int>(cur.capacity);
  const auto n = static_cast<cl_int>(count_);
  const cl_float4 centre{
      {params_.region_centre.x(), params_.region_centre.y(), params_.region_centre.z(), 0.0f}};
  select_init_ = {static_cast<cl_uint>(excess), 0, 0, 0, 0, 0, 0, 0};
  q.enqueueWriteBuffer(select_state_, CL_FALSE, 0, sizeof(select_init_), select_init_.data());
  // (word, shift) from the top: the shell's 16 bits, the confidence's 32, the index's 24.
  constexpr std::array<std::array<int, 2>, 9> passes{
      {{0, 8}, {0, 0}, {1, 24}, {1, 16}, {1, 8}, {1, 0}, {2, 16}, {2, 8}, {2, 0}}};
  const std::size_t chunks = (count_ + kHistogramChunk - 1) / kHistogramChunk;
  for (const auto& [word, shift] : passes) {
    set_args(histogram_, cur.floats, cap, n, centre, params_.eviction_shell_m, select_state_,
             static_cast<cl_int>(word), static_cast<cl_int>(shift),
             static_cast<cl_int>(kHistogramChunk), histogram_buf_);
    run_1d(histogram_, chunks, 1);
    set_args(select_, histogram_buf_, select_state_, static_cast<cl_int>(word),
             static_cast<cl_int>(shift));
    run_1d(select_, 1, 1);
  }
  const std::size_t blocks = (count_ + kBlock - 1) / kBlock;
  set_args(keep_below_, cur.floats, cap, n, centre, params_.eviction_shell_m, select_state_, keep_,
           block_kept_);
  run_1d(keep_below_, blocks, kLocalWalk);
  // The scan with no rows: only the blocks' offsets are wanted (the frame's totals were read;
  // what it sums of the frame's violated and stale counts is not).
  set_args(scan_, block_kept_, block_violated_, block_stale_, static_cast<cl_int>(blocks),
           fused_rows_, born_rows_, static_cast<cl_int>(0), totals_);
  run_1d(scan_, 1, 1);
  set_args(compact_, cur.floats, cur.frames, cur.flags, cap, n, keep_, block_kept_, next.floats,
           next.frames, next.flags, static_cast<cl_int>(next.capacity));
  run_1d(compact_, blocks, kLocalWalk);
  current_ = 1 - current_;
  count_ -= excess;
}

std::vector<Surfel> SurfelMapDevice::download() {
  std::vector<Surfel> out(count_);
  if (count_ == 0) return out;
  const SurfelSet& s = sets_[current_];
  auto& q = ctx_.queue();
  std::vector<float> floats(kFloatPlanes * count_);
  std::vector<cl_long> frames(2 * count_);
  std::vector<std::uint8_t> flags(count_);
  for (std::size_t p = 0; p < kFloatPlanes; ++p)
    q.enqueueReadBuffer(s.floats, CL_FALSE, p * s.capacity * sizeof(float), count_ * sizeof(float),
                        floats.data() + p * count_);
  for (std::size_t p = 0; p < 2; ++p)
    q.enqueueReadBuffer(s.frames, CL_FALSE, p * s.capacity * sizeof(cl_long),
                        count_ * sizeof(cl_long), frames.data() + p * count_);
  q.enqueueReadBuffer(s.flags, CL_TRUE, 0, count_, flags.data());
  const auto plane = [&](std::size_t p, std::size_t i) { return floats[p * count_ + i]; };
  for (std::size_t i = 0; i < count_; ++i) {
    Surfel& o = out[i];
    o.position = {plane(0, i), plane(1, i), plane(2, i)};
    o.normal = {plane(3, i), plane(4, i), plane(5, i)};
    o.radius = plane(6, i);
    o.confidence = plane(7, i);
    o.radiance = {plane(8, i), plane(9, i), plane(10, i)};
    o.flags = flags[i];
    o.created_frame = frames[i];
    o.last_seen_frame = frames[count_ + i];
  }
  return out;
}

}  // namespace probeless::fusion
