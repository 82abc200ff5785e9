#include "kernels/tracking/tracking_device.hpp"

#include <algorithm>
#include <stdexcept>

#include "kernels/tracking/dense_tracker.hpp"
#include "kernels/tracking/tracking_cl.hpp"

namespace probeless::tracking {
namespace {

// 64 items per group (>= the 40 sums the group reduces, one per item) and at most 32 groups:
// on PoCL's 2 CPU cores more groups only add scheduling; each item takes a few points.
constexpr int kLocal = 64;
constexpr int kMaxGroups = 32;
const std::string kOptions = "-DLOCAL=" + std::to_string(kLocal);

}  // namespace

TrackingDevice::TrackingDevice(ComputeContext& ctx)
    : ctx_(ctx),
      finest_(ctx.kernel("tracking", cl_source::tracking, kOptions, "finest_level")),
      undistort_(ctx.kernel("tracking", cl_source::tracking, kOptions, "undistort")),
      halve_(ctx.kernel("tracking", cl_source::tracking, kOptions, "halve")),
      accumulate_(
          ctx.kernel("tracking", cl_source::tracking, kOptions, "accumulate_normal_equations")),
      select_(ctx.kernel("tracking", cl_source::tracking, kOptions, "select_points")),
      partial_(ctx.context(), CL_MEM_WRITE_ONLY, sizeof(float) * kSumCount * kMaxGroups),
      partial_host_(std::size_t(kSumCount * kMaxGroups)) {}

void TrackingDevice::build_pyramid(const ImageRGB8& colour, const DepthImage& depth_mm,
                                   const PinholeIntrinsics& camera,
                                   const DenseTrackerParams& params) {
  auto& q = ctx_.queue();
  colour_.upload(q, colour, false);
  depth_mm_.upload(q, depth_mm, false);
  levels_.resize(std::size_t(params.levels));
  for (int i = 0; i < params.levels; ++i) {
    Level& l = levels_[std::size_t(i)];
    l.camera = level_camera(camera, params.finest_level + i);
    l.intensity.resize(ctx_.context(), l.camera.width, l.camera.height);
    l.depth_m.resize(ctx_.context(), l.camera.width, l.camera.height);
  }
  const bool undistort = map_size_ > 0;
  if (undistort &&
      map_size_ != 2 * std::size_t(levels_[0].camera.width) * std::size_t(levels_[0].camera.height))
    throw std::invalid_argument("tracking: the undistortion map is not the finest level's size");
  const Level& f = undistort ? distorted_ : levels_[0];
  if (undistort) {
    distorted_.camera = levels_[0].camera;
    distorted_.intensity.resize(ctx_.context(), f.camera.width, f.camera.height);
    distorted_.depth_m.resize(ctx_.context(), f.camera.width, f.camera.height);
  }
  finest_.setArg(0, colour_.buffer());
  finest_.setArg(1, depth_mm_.buffer());
  finest_.setArg(2, colour.width());
  finest_.setArg(3, params.finest_level == 0 ? 1 : 2);
  finest_.setArg(4, params.min_depth_m);
  finest_.setArg(5, params.max_depth_m);
  finest_.setArg(6, f.intensity.buffer());
  finest_.setArg(7, f.depth_m.buffer());
  finest_.setArg(8, f.camera.width);
  finest_.setArg(9, f.camera.height);
  ctx_.run_2d(finest_, f.camera.width, f.camera.height);
  if (undistort) {
    const Level& out = levels_[0];
    undistort_.setArg(0, f.intensity.buffer());
    undistort_.setArg(1, f.depth_m.buffer());
    undistort_.setArg(2, undistort_map_);
    undistort_.setArg(3, out.intensity.buffer());
    undistort_.setArg(4, out.depth_m.buffer());
    undistort_.setArg(5, out.camera.width);
    undistort_.setArg(6, out.camera.height);
    ctx_.run_2d(undistort_, out.camera.width, out.camera.height);
  }
  for (std::size_t i = 1; i < levels_.size(); ++i) {
    const Level &in = levels_[i - 1], &out = levels_[i];
    halve_.setArg(0, in.intensity.buffer());
    halve_.setArg(1, in.depth_m.buffer());
    halve_.setArg(2, in.camera.width);
    halve_.setArg(3, out.intensity.buffer());
    halve_.setArg(4, out.depth_m.buffer());
    halve_.setArg(5, out.camera.width);
    halve_.setArg(6, out.camera.height);
    ctx_.run_2d(halve_, out.camera.width, out.camera.height);
  }
  // The uploads were not blocking: the host images must not be needed after we return.
  q.finish();
}

void TrackingDevice::set_undistortion(const std::vector<float>& map) {
  map_size_ = map.size();
  if (map.empty()) return;
  undistort_map_ = ::cl::Buffer(ctx_.context(), CL_MEM_READ_ONLY, sizeof(float) * map.size());
  ctx_.queue().enqueueWriteBuffer(undistort_map_, CL_TRUE, 0, sizeof(float) * map.size(),
                                  map.data());
}

void TrackingDevice::download_pyramid(FramePyramid& pyramid) {
  pyramid.levels.resize(levels_.size());
  for (std::size_t i = 0; i < levels_.size(); ++i) {
    pyramid.levels[i].camera = levels_[i].camera;
    levels_[i].intensity.download(ctx_.queue(), pyramid.levels[i].intensity);
    levels_[i].depth_m.download(ctx_.queue(), pyramid.levels[i].depth_m);
  }
}

Keyframe TrackingDevice::make_keyframe(const Pose& T_world_keyframe, int max_points_per_level,
                                       const std::array<float, 3>& readout_rotation) {
  Keyframe keyframe;
  keyframe.T_world_keyframe = T_world_keyframe;
  auto& q = ctx_.queue();
  for (const Level& l : levels_) {
    keyframe.cameras.push_back(l.camera);
    auto& points = keyframe.points.emplace_back();
    const int w = l.camera.width, h = l.camera.height;
    if (w < 3 || h < 3) continue;
    const int block = point_block_size(w, h, max_points_per_level);
    const int blocks_x = (w - 2 + block - 1) / block, blocks_y = (h - 2 + block - 1) / block;
    const auto blocks = std::size_t(blocks_x) * std::size_t(blocks_y);
    if (blocks > slots_capacity_) {
      slots_ = ::cl::Buffer(ctx_.context(), CL_MEM_READ_WRITE, sizeof(TrackPoint) * blocks);
      slots_capacity_ = blocks;
    }
    select_.setArg(0, l.intensity.buffer());
    select_.setArg(1, l.depth_m.buffer());
    select_.setArg(2, w);
    select_.setArg(3, h);
    select_.setArg(4, cl_float4{{l.camera.fx, l.camera.fy, l.camera.cx, l.camera.cy}});
    select_.setArg(5, block);
    select_.setArg(6, blocks_x);
    select_.setArg(7, blocks_y);
    select_.setArg(8, slots_);
    q.enqueueNDRangeKernel(select_, ::cl::NullRange, ::cl::NDRange(round_up(blocks, kLocal)),
                           ::cl::NullRange);
    slots_host_.resize(blocks);
    q.enqueueReadBuffer(slots_, CL_TRUE, 0, sizeof(TrackPoint) * blocks, slots_host_.data());
    for (const TrackPoint& p : slots_host_)
      if (p.valid > 0.0f) points.push_back(p);
  }
  undo_rolling_shutter(keyframe, readout_rotation);
  upload_points(keyframe);
  return keyframe;
}

void TrackingDevice::upload_points(Keyframe& keyframe) {
  if (keyframe.device_points.size() == keyframe.points.size()) return;
  keyframe.device_points.clear();
  for (const auto& level : keyframe.points) {
    // OpenCL has no empty buffers: a level without points gets one unused point.
    const std::size_t bytes = sizeof(TrackPoint) * std::max<std::size_t>(1, level.size());
    ::cl::Buffer buffer(ctx_.context(), CL_MEM_READ_ONLY, bytes);
    if (!level.empty())
      ctx_.queue().enqueueWriteBuffer(buffer, CL_TRUE, 0, sizeof(TrackPoint) * level.size(),
                                      level.data());
    keyframe.device_points.push_back(std::move(buffer));
  }
}

NormalSums TrackingDevice::accumulate(const Keyframe& keyframe, int level,
                                      const IterationParams& params) {
  NormalSums sums{};
  const auto count = int(keyframe.points[std::size_t(level)].size());
  if (count == 0) return sums;
  const Level& l = levels_[std::size_t(level)];
  const int groups = std::clamp((count + kLocal * 4 - 1) / (kLocal * 4), 1, kMaxGroups);
  accumulate_.setArg(0, keyframe.device_points[std::size_t(level)]);
  accumulate_.setArg(1, count);
  accumulate_.setArg(2, l.intensity.buffer());
  accumulate_.setArg(3, l.depth_m.buffer());
  accumulate_.setArg(4, l.camera.width);
  accumulate_.setArg(5, l.camera.height);
  accumulate_.setArg(6, sizeof(IterationParams), &params);
  accumulate_.setArg(7, partial_);
  auto& q = ctx_.queue();
  q.enqueueNDRangeKernel(accumulate_, ::cl::NullRange, ::cl::NDRange(std::size_t(groups * kLocal)),
                         ::cl::NDRange(kLocal));
  q.enqueueReadBuffer(partial_, CL_TRUE, 0, sizeof(float) * kSumCount * std::size_t(groups),
                      partial_host_.data());
  for (int g = 0; g < groups; ++g)
    for (int k = 0; k < kSumCount; ++k)
      sums[std::size_t(k)] += double(partial_host_[std::size_t(g * kSumCount + k)]);
  return sums;
}

}  // namespace probeless::tracking
