#include "kernels/occlusion/temporal/matte_stabiliser.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include "kernels/occlusion/common/vector16_cl.hpp"
#include "kernels/occlusion/cvf/hole_core_reference.hpp"
#include "kernels/occlusion/temporal/matte_stabiliser_cl.hpp"

namespace probeless::occlusion {
namespace {

// matte_stabiliser.cl's Motion, field for field (21 floats).
struct MotionArg {
  std::array<cl_float, 9> r;
  std::array<cl_float, 3> t;
  cl_float fx, fy, cx, cy;
  cl_float history_weight, colour_range, depth_tol_mm, depth_tol_rel, snap;
};
static_assert(sizeof(MotionArg) == 21 * sizeof(cl_float));

const std::string& stabiliser_source() {
  static const std::string source =
      std::string(cl_source::vector16) + std::string(cl_source::matte_stabiliser);
  return source;
}

}  // namespace

MatteStabiliser::MatteStabiliser(ComputeContext& ctx, StabiliserParams params)
    : ctx_(ctx),
      params_(params),
      kernel_(ctx.kernel("matte_stabiliser", stabiliser_source(),
                         fmt::format("-DUNCONFIRMED_RANGE={:a}f -DNEAR_MM={} "
                                     "-DCONFIRMED_WEIGHT={:a}f -DNEAR_WEIGHT={:a}f",
                                     double(params.unconfirmed_colour_range), kNearHoleDepthMm,
                                     double(params.confirmed_history_weight),
                                     double(params.near_occluder_history_weight)),
                         "stabilise_matte")) {
  for (const float weight : {params.history_weight, params.confirmed_history_weight,
                             params.near_occluder_history_weight})
    if (!(weight >= 0.f && weight < 1.f))
      throw std::invalid_argument("matte stabiliser: history weights must lie in [0, 1)");
  if (!(params.colour_range > 0.f && params.unconfirmed_colour_range > 0.f))
    throw std::invalid_argument("matte stabiliser: colour ranges must be > 0");
  if (!(params.depth_tolerance_mm >= 0.f && params.depth_tolerance_rel >= 0.f))
    throw std::invalid_argument("matte stabiliser: depth tolerances must be >= 0");
  if (!(params.snap >= 0.f && params.snap < 0.5f))
    throw std::invalid_argument("matte stabiliser: snap must lie in [0, 0.5)");
}

void MatteStabiliser::process(const OcclusionInputs& in, const PinholeIntrinsics& k,
                              const std::optional<Pose>& T_world_camera,
                              DeviceImage<float, 1>& alpha) {
  check_inputs(in, "matte stabiliser");
  if (!alpha.same_size(*in.colour))
    throw std::invalid_argument("matte stabiliser: the matte differs in size from the frame");
  const int w = in.width(), h = in.height();
  if (!history_[previous_].same_size(w, h)) {
    have_previous_ = false;
    for (int b = 0; b < 2; ++b) {
      history_[b].resize(ctx_.context(), w, h);
      depth_[b].resize(ctx_.context(), w, h);
      flagged_rows_[b] = PixelRect::whole(w, h);
    }
  }
  if (w > 0 && h > 0) {
    Pose T_prev_curr;  // identity without both poses
    if (have_previous_ && T_world_camera && previous_pose_)
      T_prev_curr = previous_pose_->inverse() * *T_world_camera;
    MotionArg m{};
    const Eigen::Matrix3d r = T_prev_curr.rotation.toRotationMatrix();
    for (int i = 0; i < 9; ++i)
      m.r[static_cast<std::size_t>(i)] = static_cast<float>(r(i / 3, i % 3));
    for (int i = 0; i < 3; ++i)
      m.t[static_cast<std::size_t>(i)] = static_cast<float>(T_prev_curr.translation[i] * 1000.0);
    m.fx = static_cast<float>(k.fx);
    m.fy = static_cast<float>(k.fy);
    m.cx = static_cast<float>(k.cx);
    m.cy = static_cast<float>(k.cy);
    m.history_weight = params_.history_weight;
    m.colour_range = params_.colour_range;
    m.depth_tol_mm = params_.depth_tolerance_mm;
    m.depth_tol_rel = params_.depth_tolerance_rel;
    m.snap = params_.snap;
    // Strips of rows, one work-item each: a few per compute unit so that a strip with more of
    // the object does not leave the other units idle.
    const int next = 1 - previous_;
    // The object's rows, and those where the buffer written now held it: off the object the
    // kernel writes "no object" into the history, which clears them.
    const PixelRect object_rows = in.object_rect();
    const PixelRect rows = unite(object_rows, flagged_rows_[next]);
    flagged_rows_[next] = object_rows;
    const int strips = std::min(std::max(rows.height(), 1),
                                8 * std::max(1, static_cast<int>(ctx_.info().compute_units)));
    const int strip_rows = std::max(1, (rows.height() + strips - 1) / strips);
    const int groups = (rows.height() + strip_rows - 1) / strip_rows;
    int a = 0;
    kernel_.setArg(a++, alpha.buffer());
    kernel_.setArg(a++, in.colour->buffer());
    kernel_.setArg(a++, in.real_depth_mm->buffer());
    kernel_.setArg(a++, in.virtual_depth_mm->buffer());
    kernel_.setArg(a++, history_[previous_].buffer());
    kernel_.setArg(a++, depth_[previous_].buffer());
    kernel_.setArg(a++, history_[next].buffer());
    kernel_.setArg(a++, depth_[next].buffer());
    kernel_.setArg(a++, w);
    kernel_.setArg(a++, h);
    kernel_.setArg(a++, rows.y0);
    kernel_.setArg(a++, rows.y1);
    kernel_.setArg(a++, strip_rows);
    kernel_.setArg(a++, have_previous_ ? 1 : 0);
    kernel_.setArg(a++, sizeof(m), &m);
    if (groups > 0)
      ctx_.queue().enqueueNDRangeKernel(kernel_, ::cl::NullRange,
                                        ::cl::NDRange(1, static_cast<std::size_t>(groups)),
                                        ::cl::NDRange(1, 1));
    previous_ = next;  // this frame becomes the previous one
  }
  previous_pose_ = T_world_camera;
  have_previous_ = true;
}

}  // namespace probeless::occlusion
