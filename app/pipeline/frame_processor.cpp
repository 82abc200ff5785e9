#include "app/pipeline/frame_processor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <utility>

#include "app/outputs/banner.hpp"
#include "app/pipeline/scene_objects.hpp"

namespace probeless {

namespace {

std::unique_ptr<ComputeContext> make_context(const ServiceConfig& config) {
  ComputeOptions options;
  if (!config.cl_platform.empty()) options.selector.platform_substring = config.cl_platform;
  if (!config.cl_device.empty()) options.selector.device_substring = config.cl_device;
  return std::make_unique<ComputeContext>(options);
}

// Runs one stage, its time recorded under its name.
template <typename Stage, typename... Args>
decltype(auto) timed(StageStats& stats, Stage& stage, Args&&... args) {
  const auto t0 = std::chrono::steady_clock::now();
  decltype(auto) result = stage.process(std::forward<Args>(args)...);
  stats.record(Stage::name, ms_since(t0));
  return result;
}

}  // namespace

occlusion::MethodParams occlusion_params(const ServiceConfig& config) {
  occlusion::MethodParams params;
  if (!config.occlusion_near_occluders) params.cvf.hole_core_px = 0;
  return params;
}

BeyondRangeRule beyond_range_rule(const ServiceConfig& config) {
  BeyondRangeRule rule;
  rule.far_mm = static_cast<std::uint16_t>(std::lround(config.occlusion_beyond_range_m * 1000.0));
  return rule;
}

FrameProcessor::FrameProcessor(const ServiceConfig& config, const RigCalibration& calibration,
                               bool keep_matte, LightSource light,
                               std::shared_ptr<PoseHistory> poses)
    : calibration_(calibration),
      keep_matte_(keep_matte),
      ctx_(make_context(config)),
      render_(make_scene_objects(config.objects, config.ground, default_prt_cache_dir()),
              calibration.rgb.intrinsics(), std::move(light)),
      upload_(*ctx_, calibration.rgb, beyond_range_rule(config)),
      occlusion_(*ctx_,
                 occlusion::make_method(*ctx_, config.occlusion_method, occlusion_params(config)),
                 config.occlusion_stabilise, calibration.rgb.intrinsics()),
      composite_(*ctx_),
      download_(*ctx_, keep_matte),
      localiser_(config.tracking, config.world, calibration, ctx_.get()),
      poses_(std::move(poses)) {}

// Never a virtual object at a pose that may be wrong (issue #17): the camera's picture, a
// transparent matte, and a banner naming what is missing.
CompositeFrame FrameProcessor::camera_only(const RgbdFrame& frame,
                                           const world::LocaliserStatus& s) const {
  auto colour = std::make_shared<ImageRGB8>(frame.colour);
  const std::string text = !s.anchor_found && s.state == tracking::TrackingState::Tracking
                               ? "LOOKING FOR THE " + s.anchor
                               : "TRACKING " + std::string(tracking::to_string(s.state));
  const int scale = std::max(1, colour->height() / 240);
  const int pad = 2 * scale;
  const int w = std::min(colour->width(), text_width(text, scale) + 2 * pad);
  const int h = std::min(colour->height(), text_height(scale) + 2 * pad);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) colour->at(x, y, c) = 0;
  draw_text(*colour, pad, pad, text, scale, {255, 200, 0});

  CompositeFrame out;
  out.sequence = frame.sequence;
  out.timestamp_ns = frame.timestamp_ns;
  out.colour = std::move(colour);
  if (keep_matte_) {
    out.alpha = std::make_shared<const ImageF>(frame.colour.width(), frame.colour.height(), 0.0f);
    out.virtual_depth = out.alpha;  // 0 mm: no object anywhere
  }
  out.truth = frame.truth;
  return out;
}

CompositeFrame FrameProcessor::process(const RgbdFrame& frame, StageStats& stats) {
  return compose(frame, locate(frame, stats), stats);
}

FrameProcessor::Located FrameProcessor::locate(const RgbdFrame& frame, StageStats& stats) {
  Located located;
  located.started = std::chrono::steady_clock::now();
  // Before tracking, whose own check names neither size (vm_board_run, issue #18).
  upload_.check_size(frame);
  located.T_world_rig = localiser_.locate(frame);
  stats.record("tracking", ms_since(located.started));
  located.status = localiser_.status();
  if (poses_) {
    if (located.T_world_rig)
      poses_->add(frame.timestamp_ns, *located.T_world_rig);
    else
      poses_->mark_unknown(frame.timestamp_ns);
  }
  return located;
}

CompositeFrame FrameProcessor::compose(const RgbdFrame& frame, const Located& located,
                                       StageStats& stats) {
  return finish(submit(frame, located, stats), stats);
}

// From an empty one (release() is a no-op there): the transfer is written once, below.
FrameProcessor::InFlight::InFlight(InFlight&& other) noexcept {
  *this = std::move(other);
}

FrameProcessor::InFlight& FrameProcessor::InFlight::operator=(InFlight&& other) noexcept {
  if (this != &other) {
    release();
    owner_ = std::exchange(other.owner_, nullptr);
    slot_ = std::exchange(other.slot_, -1);
    pending_ = std::exchange(other.pending_, std::nullopt);
    out_ = std::move(other.out_);
    started_ = other.started_;
  }
  return *this;
}

FrameProcessor::InFlight::~InFlight() {
  release();
}

void FrameProcessor::InFlight::release() noexcept {
  if (pending_) {
    try {
      pending_->done.wait();
    } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor's wait; finish() reports
      // The event failed: the queue is broken, nothing more can be waited for.
    }
    pending_.reset();
  }
  if (owner_ && slot_ >= 0) owner_->slot_busy_[slot_] = false;
  owner_ = nullptr;
  slot_ = -1;
}

FrameProcessor::InFlight FrameProcessor::submit(const RgbdFrame& frame, const Located& located,
                                                StageStats& stats) {
  InFlight f;
  f.started_ = located.started;
  const std::optional<Pose>& T_world_rig = located.T_world_rig;
  if (!T_world_rig) {
    occlusion_.skip_frame();
    f.out_ = camera_only(frame, located.status);  // no device work: finish() just returns it
    return f;
  }
  const auto idle = std::find_if(std::begin(slot_busy_), std::end(slot_busy_),
                                 [](const std::atomic<bool>& b) { return !b.load(); });
  if (idle == std::end(slot_busy_))
    throw std::logic_error("FrameProcessor::submit: finish a frame first (two in flight)");
  const int slot = static_cast<int>(idle - std::begin(slot_busy_));
  const Pose T_world_camera = *T_world_rig * calibration_.T_rig_rgb;
  try {
    const VirtualLayer layer = timed(stats, render_, T_world_camera, slot);
    const DeviceFrame device = timed(stats, upload_, frame, layer, slot);
    const DeviceImageF& matte = timed(stats, occlusion_, device, T_world_camera);
    const DeviceImageRGB8& composite = timed(stats, composite_, device, matte);
    f.pending_ = download_.process(composite, matte);
    f.owner_ = this;
    f.slot_ = slot;
    slot_busy_[slot] = true;
    if (keep_matte_) {
      f.out_.virtual_depth = std::make_shared<const ImageF>(*layer.depth_mm);
      f.out_.T_world_camera = T_world_camera;
    }
  } catch (...) {
    // Some of this frame's commands may be queued, reading `frame` and the slot's host
    // memory, which the caller frees while unwinding: wait for them (and for the frame in
    // flight before it, whose event stays valid) before the exception leaves.
    f.release();
    try {
      ctx_->queue().finish();
    } catch (...) {  // NOLINT(bugprone-empty-catch): the first error is the one to report
    }
    throw;
  }
  f.out_.sequence = frame.sequence;
  f.out_.timestamp_ns = frame.timestamp_ns;
  f.out_.truth = frame.truth;
  return f;
}

CompositeFrame FrameProcessor::finish(InFlight in_flight, StageStats& stats) {
  if (in_flight.pending_) {
    const auto t0 = std::chrono::steady_clock::now();
    HostImages host = DownloadStage::wait(*in_flight.pending_);
    stats.record(DownloadStage::name, ms_since(t0));
    in_flight.pending_.reset();
    in_flight.out_.colour = std::move(host.composite);
    in_flight.out_.alpha = std::move(host.matte);
  }
  stats.record("frame", ms_since(in_flight.started_));
  CompositeFrame out = std::move(in_flight.out_);
  in_flight.release();  // frees the slot for the next submit
  return out;
}

}  // namespace probeless
