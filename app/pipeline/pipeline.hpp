#pragma once
// The service's pipeline (docs/architecture.md "The running service"): one capture thread per
// source, one processing thread (EGL + OpenCL live there), one output thread that hands each
// composite to every output (app/outputs/output.hpp), encoding the JPEG once when one wants it.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <semaphore>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "app/outputs/output.hpp"
#include "app/pipeline/pose_history.hpp"
#include "app/pipeline/service_config.hpp"
#include "app/service/heartbeat.hpp"
#include "app/service/systemd_notifier.hpp"
#include "app/service/watchdog.hpp"
#include "base/latest_frame.hpp"
#include "base/stage_stats.hpp"
#include "core/frame.hpp"
#include "drivers/source.hpp"
#include "drivers/trigger/exposure_trigger.hpp"

namespace probeless {

class LightCapture;
class GpioStrobe;
namespace world {
struct LocaliserStatus;
}

// What the processing thread publishes per frame.
struct CompositeFrame {
  std::uint64_t sequence = 0;  // the RGB-D frame's
  TimestampNs timestamp_ns = 0;
  std::shared_ptr<const ImageRGB8> colour;
  std::shared_ptr<const ImageF> alpha;  // with PipelineOptions::keep_matte or an output's need
  std::shared_ptr<const ImageF> virtual_depth;  // with keep_matte (mm, 0 = no object)
  std::optional<Pose> T_world_camera;  // with keep_matte: the pose it was drawn and matted with
  std::shared_ptr<const FrameTruth> truth;
  bool no_signal = false;  // a repeat of the last good frame with the NO SIGNAL banner
};

struct PipelineOptions {
  // Capture waits until processing took the previous frame, so no frame is dropped: for
  // benchmarks and tests that count frames. The service runs lossy (latest frame wins).
  bool lossless = false;
  bool keep_matte = false;
  bool serve_http = true;  // HTTP and RTSP from config; false: none (benchmarks)
  // Fed besides the outputs from config (the benchmark's JPEG sink, tests).
  std::vector<std::shared_ptr<Output>> outputs;
  // WATCHDOG=1 while every thread that matters beats (app/service/watchdog.hpp) when set.
  SystemdNotifier* notifier = nullptr;
  // Fault injection for the watchdog test (`run --fault-hang-after N`): after N frames the
  // processing loop stops working, as one stuck in a driver or OpenCL call would: no frames,
  // no WATCHDOG=1, while every other thread goes on. It still honours stop(), so the test
  // can end it with SIGTERM. -1: off.
  std::int64_t hang_after_frames = -1;
  // Fault injection for the watchdog tests of the other threads (`run --fault-hang
  // THREAD:N`): the heartbeat called `hang_thread` ("light", "output", "http", "rtsp") blocks
  // at its N-th beat (HeartbeatRegistry::wedge_after) until stop(). Empty: off.
  std::string hang_thread;
  std::int64_t hang_after_beats = -1;
};

class Pipeline {
 public:
  // Throws on a configuration the rig cannot satisfy (an object without a position on a
  // rig that has no anchor) and when the HTTP port cannot be bound.
  Pipeline(ServiceConfig config, Rig rig, PipelineOptions options = {});
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  void start();
  // Stops and joins every thread; idempotent. Returns within about one frame period.
  void stop();

  // Until the first composite is out (true), or the pipeline failed or time ran out (false).
  bool wait_first_frame(std::chrono::milliseconds timeout);
  // Until finished() or timeout; true when finished.
  bool wait_finished(std::chrono::milliseconds timeout);
  // max_frames processed, the source ended, or a fatal error (see fatal_error()).
  bool finished() const { return finished_.load(); }
  std::optional<std::string> fatal_error() const;

  nlohmann::json status() const;
  std::string url() const;       // the HTTP viewer's, empty without HTTP
  std::string rtsp_url() const;  // the H.264 stream's, empty without RTSP
  LatestFrame<CompositeFrame>& output() { return output_; }
  const StageStats& stats() const { return stats_; }
  std::uint64_t frames_processed() const { return processed_.load(); }
  std::uint64_t frames_out() const { return encoded_.load(); }
  // JPEGs encoded by the output thread: one per frame out while an output wants JPEG, else 0.
  std::uint64_t jpeg_encodes() const { return jpeg_encodes_.load(); }

 private:
  void capture_rgbd(std::stop_token stop);
  void capture_fisheye(std::stop_token stop);
  void stamp_fisheye_frame(FisheyeFrame& frame);
  void process(std::stop_token stop);
  void process_loop(std::stop_token stop, class FrameProcessor& processor);
  // One finished frame to the outputs, on the finisher thread (frame_finisher.hpp); false
  // when no more are wanted (max_frames, fault injection).
  bool publish(CompositeFrame out, const world::LocaliserStatus& status, std::stop_token stop);
  void open_outputs();  // from config and options, in start()
  void output_loop(std::stop_token stop);
  std::string url_of(std::string_view output) const;
  void publish_no_signal(const std::string& state);
  void fail(const std::string& what);
  void finish();

  ServiceConfig config_;
  Rig rig_;
  PipelineOptions options_;
  // First among the members that threads use, so it outlives every Heartbeat.
  HeartbeatRegistry heartbeats_;
  StageStats stats_;
  RateMeter fps_;
  TimestampNs started_ns_ = 0;

  LatestFrame<RgbdFrame> rgbd_slot_;
  std::counting_semaphore<1> rgbd_credit_{1};  // lossless mode only
  std::atomic<TimestampNs> last_rgbd_ns_{0};
  std::atomic<bool> rgbd_ended_{false};
  std::atomic<std::uint64_t> rgbd_in_{0};

  mutable std::mutex fisheye_mutex_;
  std::uint64_t fisheye_in_ = 0;
  std::optional<ExposureStamp> fisheye_exposure_;  // of the newest fisheye frame
  // Driven from the fisheye capture thread only (status reads copies under fisheye_mutex_).
  std::unique_ptr<BracketSequencer> bracket_;
  std::unique_ptr<ExposureTrigger> trigger_;
  std::unique_ptr<LightCapture> light_;  // null: no fisheye, light off, or unsupported
  int bracket_stops_[3] = {0, 0, 0};     // L, M, H relative to the initial exposure

  // [bracket] strobe_chip: its edges stamp the fisheye frames (capture thread only).
  std::unique_ptr<GpioStrobe> strobe_;
  std::atomic<std::uint64_t> strobe_stamped_{0};
  std::atomic<bool> strobe_failed_{false};  // the line failed: frames keep driver times

  LatestFrame<CompositeFrame> output_;
  // Lossless mode: the processing thread publishes a composite only once the output thread
  // has taken the last one, so every processed frame reaches the outputs (tests, benches).
  // Written by the finisher thread per frame and by the processing thread's NO SIGNAL
  // repeats, never both at once (the repeats wait for an empty finisher).
  std::atomic<LatestFrame<CompositeFrame>::Sequence> output_published_{0};
  std::atomic<LatestFrame<CompositeFrame>::Sequence> output_taken_{0};
  std::mutex last_good_mutex_;  // the finisher writes it, the NO SIGNAL repeats read it
  std::optional<CompositeFrame> last_good_;
  std::atomic<bool> no_signal_{false};
  std::atomic<std::uint64_t> processed_{0};
  std::atomic<std::uint64_t> encoded_{0};  // frames handed to the outputs
  std::atomic<std::uint64_t> jpeg_encodes_{0};

  // From config, then PipelineOptions::outputs; built in start() while the HTTP server may
  // already ask for status(), hence the mutex (the output thread starts after them).
  mutable std::mutex outputs_mutex_;
  std::vector<std::shared_ptr<Output>> outputs_;
  OutputNeeds needs_;  // what any of them needs

  mutable std::mutex state_mutex_;
  std::condition_variable state_changed_;
  std::optional<std::string> fatal_;
  std::string occlusion_name_, device_name_;  // set once the processing thread is up
  nlohmann::json tracking_;  // /status "tracking", from the processing thread after each frame
  // The processing thread's rig poses for the light thread (docs/tracking.md).
  std::shared_ptr<PoseHistory> poses_ = std::make_shared<PoseHistory>();
  std::atomic<bool> finished_{false};
  bool first_out_ = false;
  bool stopped_ = false;

  std::vector<std::jthread> threads_;
  std::unique_ptr<ServiceWatchdog> watchdog_;
};

}  // namespace probeless
