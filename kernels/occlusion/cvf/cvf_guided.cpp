#include "kernels/occlusion/cvf/cvf_guided.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "kernels/occlusion/common/vector16_cl.hpp"
#include "kernels/occlusion/cvf/cvf_guided_cl.hpp"
#include "kernels/occlusion/cvf/cvf_vector_cl.hpp"

namespace probeless::occlusion {

StripGuidedFilter::StripGuidedFilter(ComputeContext& ctx, int radius, float eps, Input input,
                                     Output output, const std::string& extra_options, bool trace)
    : ctx_(ctx), radius_(radius), eps_(eps) {
  if (radius < 0 || radius > kMaxRadius)
    throw std::invalid_argument(
        fmt::format("StripGuidedFilter: radius {} outside 0..{}", radius, kMaxRadius));
  const auto opts = fmt::format("-DRADIUS={} -DINPUT_MODE={} -DOUTPUT_MODE={} -DTRACE={} {}",
                                radius, int(input), int(output), trace ? 1 : 0, extra_options);
  static const std::string source = std::string(cl_source::vector16) +
                                    std::string(cl_source::cvf_vector) +
                                    std::string(cl_source::cvf_guided);
  kernel_ = ctx.kernel("cvf_guided", source, opts, "gf_strip");
  row_object_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_ONLY, sizeof(cl_int));
}

void StripGuidedFilter::set_active_rows(const ::cl::Buffer& row_object, int n_rows, int scale,
                                        int reach) {
  row_object_ = row_object;
  n_rows_ = n_rows;
  row_scale_ = std::max(1, scale);
  reach_ = reach;
}

int StripGuidedFilter::strip_count(int h, int warmup_rows, int units) {
  units = std::max(1, units);
  const int per_unit = h / (units * 4 * std::max(1, warmup_rows));
  return std::clamp(per_unit, 1, 4) * units;
}

void StripGuidedFilter::run(int w, int h) {
  if (w <= 0 || h <= 0) return;
  // Strips of rows, one work-item each; a strip walks 3 r rows above it and r below.
  const int strips = strip_count(h, 4 * radius_, static_cast<int>(ctx_.info().compute_units));
  const int strip_rows = (h + strips - 1) / strips;
  const int groups = (h + strip_rows - 1) / strip_rows;
  const int nring = 2 * radius_ + 2;
  const std::size_t srow = StripGuidedFilter::scratch_row(w);
  const std::size_t bytes = sizeof(float) * srow * (8 * nring + 17) * groups;
  if (bytes > scratch_bytes_) {
    scratch_ = ::cl::Buffer(ctx_.context(), CL_MEM_READ_WRITE, bytes);
    scratch_bytes_ = bytes;
  }
  kernel_.setArg(0, w);
  kernel_.setArg(1, h);
  kernel_.setArg(2, strip_rows);
  kernel_.setArg(3, eps_);
  kernel_.setArg(4, scratch_);
  kernel_.setArg(5, row_object_);
  kernel_.setArg(6, n_rows_);
  kernel_.setArg(7, row_scale_);
  kernel_.setArg(8, reach_);
  ctx_.queue().enqueueNDRangeKernel(kernel_, ::cl::NullRange,
                                    ::cl::NDRange(1, static_cast<std::size_t>(groups)),
                                    ::cl::NDRange(1, 1));
}

}  // namespace probeless::occlusion
