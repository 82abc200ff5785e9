#pragma once
// What the frame path's tests share (frame_overlap_test.cpp, frame_finisher_test.cpp): the
// sim's first frames along a moving camera, a gate that holds the device's queue, and a
// frame located at its true pose.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "app/pipeline/frame_processor.hpp"
#include "app/pipeline/scene_objects.hpp"
#include "drivers/rig_factory.hpp"

namespace probeless::testing {

using namespace std::chrono_literals;

constexpr int kFrames = 4;

struct Fixture {
  Rig rig;
  ServiceConfig config;
  std::vector<RgbdFrame> frames;
};

// A moving camera (the sim's orbit), so consecutive frames differ wherever the objects are.
inline Fixture make_fixture() {
  Fixture f{open_rig("sim:realtime=0,trajectory=orbit,frames=8"), {}, {}};
  place_objects(f.config.objects, f.rig.scene);
  while (static_cast<int>(f.frames.size()) < kFrames) {
    RgbdFrame frame;
    const ReadResult r = f.rig.rgbd->read(frame, 5s);
    if (r == ReadResult::Frame) f.frames.push_back(std::move(frame));
    if (r == ReadResult::EndOfStream || r == ReadResult::Error) break;
  }
  return f;
}

// Holds the frame path's queue until release() (or 20 s at the latest, so that a submit that
// wrongly waits for the device fails the test rather than hanging it): the device then works
// on a frame only after the next one is rendered, which is when a layer shared between the
// two would be overwritten before it is read.
class QueueGate {
 public:
  explicit QueueGate(ComputeContext& ctx) : event_(ctx.context()) {
    const std::vector<::cl::Event> wait = {event_};
    ctx.queue().enqueueMarkerWithWaitList(&wait, nullptr);
    ctx.queue().flush();
    timeout_ = std::jthread([this](std::stop_token stop) {
      std::mutex m;
      std::unique_lock lock(m);
      std::condition_variable_any().wait_for(lock, stop, 20s, [] { return false; });
      release();
    });
  }
  ~QueueGate() { timeout_.request_stop(); }  // the thread releases on its way out
  void release() {
    if (!released_.exchange(true)) event_.setStatus(CL_COMPLETE);
  }
  bool released() const { return released_; }

 private:
  ::cl::UserEvent event_;
  std::atomic<bool> released_{false};
  std::jthread timeout_;
};

inline FrameProcessor::Located at_truth(const RgbdFrame& frame) {
  FrameProcessor::Located located;
  located.T_world_rig = frame.truth->rig_pose;
  located.started = std::chrono::steady_clock::now();
  return located;
}

}  // namespace probeless::testing
