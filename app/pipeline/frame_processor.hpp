#pragma once
// The processing thread's work for one RGB-D frame: the stages of frame_stages.hpp composed
// from config, each one's result the next one's input, each timed into StageStats. Owns the
// OpenCL context and the EGL renderer, so it must be created, used and destroyed on one
// thread; only finish() may run on another (the finisher, frame_finisher.hpp), one call at a
// time, beside that thread's locate() and submit() of the next frame.
//
// compose() is locate(), submit() then finish(). Apart, they let the host render frame N+1
// while the OpenCL device works on frame N (issue #19): on PoCL + llvmpipe the render (~13 ms
// with the HDR layer) and the device's matte + composite (~10 ms waited for in the download)
// ran one after the other, bounding the bench at ~35 fps with 1.65 of the 2 cores busy.
#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "app/pipeline/frame_stages.hpp"
#include "app/pipeline/pipeline.hpp"
#include "app/pipeline/pose_history.hpp"
#include "app/pipeline/service_config.hpp"
#include "app/world/rig_localiser.hpp"
#include "base/stage_stats.hpp"
#include "kernels/occlusion/method_registry.hpp"

namespace probeless {

// The occlusion method's parameters from [occlusion] (its method's defaults otherwise).
occlusion::MethodParams occlusion_params(const ServiceConfig& config);
// The sensor's beyond-range holes from [occlusion] beyond_range_m (0 turns the rule off).
BeyondRangeRule beyond_range_rule(const ServiceConfig& config);

class FrameProcessor {
 public:
  // `light`: the light capture's snapshots (LightCapture::latest_light), if it runs.
  // `poses`: where each frame's rig pose (or its absence) goes for the light thread.
  FrameProcessor(const ServiceConfig& config, const RigCalibration& calibration, bool keep_matte,
                 LightSource light = {}, std::shared_ptr<PoseHistory> poses = {});
  // Where the rig is at one frame, and /status "tracking" as of that frame.
  struct Located {
    std::optional<Pose> T_world_rig;
    world::LocaliserStatus status;
    std::chrono::steady_clock::time_point started;  // when locate() began: the frame's start
  };

  // A frame submitted and not yet finished: its device work, the host images it writes into
  // and the composite's other fields. Move-only; destroyed unfinished it waits for the device
  // (its commands read host memory: the frame's, the render target's), so an exception
  // cannot leave the device reading freed memory. Must not outlive its FrameProcessor.
  class InFlight {
   public:
    InFlight() = default;
    InFlight(InFlight&& other) noexcept;
    InFlight& operator=(InFlight&& other) noexcept;
    InFlight(const InFlight&) = delete;
    InFlight& operator=(const InFlight&) = delete;
    ~InFlight();
    // Whether it has device work to wait for (false: a camera-only frame, or moved from).
    bool on_device() const { return pending_.has_value(); }

   private:
    friend class FrameProcessor;
    void release() noexcept;  // waits (errors swallowed) and frees the slot

    FrameProcessor* owner_ = nullptr;
    int slot_ = -1;
    std::optional<PendingDownload> pending_;
    CompositeFrame out_;  // all but the downloaded images
    std::chrono::steady_clock::time_point started_;
  };

  // locate() then compose(): the frame on this thread alone.
  CompositeFrame process(const RgbdFrame& frame, StageStats& stats);
  // The tracking stage ("tracking"): the rig pose, also handed to the light thread (`poses`).
  // Frames in order, one call at a time.
  Located locate(const RgbdFrame& frame, StageStats& stats);
  // Everything after tracking: render, upload, matte, composite, download ("frame": from
  // located.started to the end). finish(submit(...)).
  CompositeFrame compose(const RgbdFrame& frame, const Located& located, StageStats& stats);
  // Renders and uploads the frame and enqueues its matte, composite and the reads of the
  // results without waiting for the device. `frame` must stay alive and in place until the
  // frame is finished. At most kFrameSlots frames on the way: one in flight beside the one
  // submitted (a third is std::logic_error). Frames are finished in the order submitted.
  // If it throws, nothing of this frame is left on the queue.
  InFlight submit(const RgbdFrame& frame, const Located& located, StageStats& stats);
  // Waits for the frame's device work ("download": the wait; "frame": from located.started
  // to here) and returns its composite. Waits on the frame's own event, not the queue, as the
  // next frame's commands may be queued behind it.
  CompositeFrame finish(InFlight in_flight, StageStats& stats);
  // Where the rig is, as of the last frame located (/status "tracking").
  const world::LocaliserStatus& tracking() const { return localiser_.status(); }

  std::string occlusion_method() const { return occlusion_.method_name(); }
  // The frame path's OpenCL context and queue (tests hold the queue back with a user event).
  ComputeContext& compute() { return *ctx_; }
  std::string device_description() const { return ctx_->describe(); }

 private:
  RigCalibration calibration_;
  bool keep_matte_;
  std::unique_ptr<ComputeContext> ctx_;
  RenderStage render_;
  UploadStage upload_;
  OcclusionStage occlusion_;
  CompositeStage composite_;
  DownloadStage download_;
  world::RigLocaliser localiser_;
  std::shared_ptr<PoseHistory> poses_;
  // By a submitted frame not yet finished; freed by finish() on the finisher thread.
  std::atomic<bool> slot_busy_[kFrameSlots] = {};

  // The camera image alone with a small banner: what is shown while the pose is unknown.
  CompositeFrame camera_only(const RgbdFrame& frame, const world::LocaliserStatus& s) const;
};

}  // namespace probeless
