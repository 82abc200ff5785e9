#include "kernels/occlusion/cvf/hole_core.hpp"

#include <stdexcept>
#include <string>

#include "kernels/occlusion/cvf/hole_core_cl.hpp"
#include "kernels/occlusion/cvf/hole_core_reference.hpp"

namespace probeless::occlusion {

HoleCoreFill::HoleCoreFill(ComputeContext& ctx) : ctx_(ctx) {
  const std::string options = "-DNEAR_MM=" + std::to_string(kNearHoleDepthMm) +
                              " -DWHITE_MIN=" + std::to_string(kFarHoleWhiteMin) +
                              " -DBLACK_MAX=" + std::to_string(kFarHoleBlackMax) +
                              " -DCORE_COLOUR_SQ=" + std::to_string(kNearRimCoreColourSq);
  rows_ = ctx.kernel("hole_core", cl_source::hole_core, options, "hole_core_rows");
  fill_ = ctx.kernel("hole_core", cl_source::hole_core, options, "hole_core_fill");
  rim_rows_ = ctx.kernel("hole_core", cl_source::hole_core, options, "near_rim_rows");
  rim_mark_ = ctx.kernel("hole_core", cl_source::hole_core, options, "near_rim_mark");
}

void HoleCoreFill::window_pass(const DeviceImage<std::uint16_t, 1>& depth, std::uint16_t value,
                               bool need_all, DeviceImage<std::uint16_t, 1>& out, int radius,
                               const DeviceImage<std::uint8_t, 3>* colour,
                               const PixelRect& needed) {
  const int w = depth.width(), h = depth.height();
  row_hits_.resize(ctx_.context(), w, h);
  out.resize(ctx_.context(), w, h);
  if (h > core_rows_size_) {
    core_rows_ = ::cl::Buffer(ctx_.context(), CL_MEM_READ_WRITE, static_cast<std::size_t>(h));
    rim_rows_flags_ = ::cl::Buffer(ctx_.context(), CL_MEM_READ_WRITE, static_cast<std::size_t>(h));
    core_rows_size_ = h;
  }
  if (needed.empty()) return;
  if (need_all)
    ctx_.queue().enqueueFillBuffer(core_rows_, cl_uchar{0}, 0, static_cast<std::size_t>(h));
  // The column pass at rows [y0, y1) reads the row pass's hits from r + 1 rows above to r
  // below (its sliding count starts with the row that leaves the window first).
  const PixelRect rows = grown(needed, radius + 1, w, h);
  int a = 0;
  rows_.setArg(a++, depth.buffer());
  rows_.setArg(a++, row_hits_.buffer());
  rows_.setArg(a++, w);
  rows_.setArg(a++, h);
  rows_.setArg(a++, radius);
  rows_.setArg(a++, static_cast<cl_ushort>(value));
  rows_.setArg(a++, need_all ? 1 : 0);
  // Without a colour image the kernel never reads it; the depth buffer stands in for it.
  rows_.setArg(a++, colour ? colour->buffer() : depth.buffer());
  rows_.setArg(a++, colour ? 1 : 0);
  // Work-groups of one work-item: PoCL would otherwise put all rows (or all column groups)
  // into one work-group, which runs on one core while the other waits.
  ctx_.queue().enqueueNDRangeKernel(rows_, ::cl::NDRange(std::size_t(rows.y0)),
                                    ::cl::NDRange(std::size_t(rows.height())), ::cl::NDRange(1));
  a = 0;
  fill_.setArg(a++, depth.buffer());
  fill_.setArg(a++, row_hits_.buffer());
  fill_.setArg(a++, out.buffer());
  fill_.setArg(a++, w);
  fill_.setArg(a++, h);
  fill_.setArg(a++, radius);
  fill_.setArg(a++, need_all ? 1 : 0);
  fill_.setArg(a++, needed.x0);
  fill_.setArg(a++, needed.x1);
  fill_.setArg(a++, needed.y0);
  fill_.setArg(a++, needed.y1);
  fill_.setArg(a++, core_rows_);
  ctx_.queue().enqueueNDRangeKernel(
      fill_, ::cl::NullRange, ::cl::NDRange(static_cast<std::size_t>((needed.width() + 15) / 16)),
      ::cl::NDRange(1));
}

const DeviceImage<std::uint16_t, 1>& HoleCoreFill::run(const DeviceImage<std::uint16_t, 1>& depth,
                                                       int radius,
                                                       const DeviceImage<std::uint8_t, 3>* colour,
                                                       const std::optional<PixelRect>& needed) {
  if (radius < 1) throw std::invalid_argument("hole core: radius must be >= 1");
  if (colour && !colour->same_size(depth))
    throw std::invalid_argument("hole core: colour and depth sizes differ");
  radius_ = radius;
  depth_ = &depth;
  const PixelRect whole = PixelRect::whole(depth.width(), depth.height());
  needed_ = needed ? intersect(*needed, whole) : whole;
  // The marks at a pixel read the filled depth r px around it.
  window_pass(depth, 0, true, filled_, radius, colour,
              grown(needed_, radius, depth.width(), depth.height()));
  return filled_;
}

const DeviceImage<std::uint16_t, 1>& HoleCoreFill::mark_near_occluders(
    const DeviceImage<std::uint8_t, 3>* colour) {
  if (radius_ < 1) throw std::logic_error("hole core: mark_near_occluders() before run()");
  if (!colour) {
    window_pass(filled_, kNearHoleDepthMm, false, marked_, radius_, nullptr, needed_);
    return marked_;
  }
  const int w = depth_->width(), h = depth_->height(), r = radius_, m = near_rim_radius(w);
  if (!colour->same_size(*depth_))
    throw std::invalid_argument("hole core: colour and depth sizes differ");
  if (r > 128) throw std::invalid_argument("hole core: the rim's colour takes radii <= 128 px");
  rim_sums_.resize(ctx_.context(), w, h);
  if (needed_.empty()) return filled_;
  // The column pass reads the row sums max(r, m) rows around `needed`, each of which reads the
  // filled depth r columns either side: inside what run() filled.
  const PixelRect rows = grown(needed_, std::max(r, m), w, h);
  int a = 0;
  rim_rows_.setArg(a++, depth_->buffer());
  rim_rows_.setArg(a++, filled_.buffer());
  rim_rows_.setArg(a++, colour->buffer());
  rim_rows_.setArg(a++, rim_sums_.buffer());
  rim_rows_.setArg(a++, w);
  rim_rows_.setArg(a++, h);
  rim_rows_.setArg(a++, r);
  rim_rows_.setArg(a++, m);
  rim_rows_.setArg(a++, needed_.x0);
  rim_rows_.setArg(a++, needed_.x1);
  rim_rows_.setArg(a++, core_rows_);
  rim_rows_.setArg(a++, rim_rows_flags_);
  // Work-groups of one work-item, as window_pass()'s.
  ctx_.queue().enqueueNDRangeKernel(rim_rows_, ::cl::NDRange(std::size_t(rows.y0)),
                                    ::cl::NDRange(std::size_t(rows.height())), ::cl::NDRange(1));
  a = 0;
  rim_mark_.setArg(a++, depth_->buffer());
  rim_mark_.setArg(a++, filled_.buffer());
  rim_mark_.setArg(a++, colour->buffer());
  rim_mark_.setArg(a++, rim_sums_.buffer());
  rim_mark_.setArg(a++, filled_.buffer());  // in place
  rim_mark_.setArg(a++, w);
  rim_mark_.setArg(a++, h);
  rim_mark_.setArg(a++, r);
  rim_mark_.setArg(a++, m);
  rim_mark_.setArg(a++, needed_.x0);
  rim_mark_.setArg(a++, needed_.x1);
  rim_mark_.setArg(a++, needed_.y0);
  rim_mark_.setArg(a++, needed_.y1);
  rim_mark_.setArg(a++, rim_rows_flags_);
  ctx_.queue().enqueueNDRangeKernel(
      rim_mark_, ::cl::NullRange,
      ::cl::NDRange(static_cast<std::size_t>((needed_.width() + 15) / 16)), ::cl::NDRange(1));
  return filled_;
}

}  // namespace probeless::occlusion
