#pragma once
// The second half of a frame's way through the processing thread, on a thread of its own
// (issue #19's frame p99): each submitted frame is waited for and published the moment the
// device has finished it, in submission order, while the processing thread locates, renders
// and submits the next one.
//
// Before, the processing thread finished frame N only after it had rendered and submitted
// frame N+1, and tracked frame N+2 on a worker meanwhile, so in `bench pipeline` (frames
// always waiting) a frame spent ~2.5 loop turns on the way: frame p50 25-32 ms, p99 49-57 at
// 88-104 fps. Published from here it spends its own work and little else: p50 ~16 ms, p99
// 30-38 at the same rate (docs/performance.md, 2026-12-08). The device's wait moved here, so
// the processing thread no longer needs the tracking worker to keep both cores busy.
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <stop_token>
#include <string>
#include <thread>

#include "app/pipeline/frame_processor.hpp"
#include "base/stage_stats.hpp"

namespace probeless {

class FrameFinisher {
 public:
  // A frame handed over: its device work reads `frame`'s images until it is finished, so it
  // lives on the heap and never moves.
  struct Submitted {
    RgbdFrame frame;
    world::LocaliserStatus status;
    FrameProcessor::InFlight work;
  };
  // Publishes one finished frame; false when no more frames are wanted (max_frames, fault
  // injection). `stop` is the finisher's, for a publish that waits.
  using Publish =
      std::function<bool(CompositeFrame, const world::LocaliserStatus&, std::stop_token stop)>;
  // A frame's device work failed (FrameProcessor::finish threw): the finisher stops.
  using Fail = std::function<void(const std::string&)>;

  // At most `capacity` frames on the way (handed over and not yet published): the slots of
  // host memory the device reads (kFrameSlots).
  FrameFinisher(FrameProcessor& processor, StageStats& stats, Publish publish, Fail fail,
                int capacity = kFrameSlots);
  // Stops the thread; frames not yet published are dropped, each waiting for its device work
  // first (FrameProcessor::InFlight).
  ~FrameFinisher();
  FrameFinisher(const FrameFinisher&) = delete;
  FrameFinisher& operator=(const FrameFinisher&) = delete;

  // Until another frame may be submitted (true), or the finisher stopped or `stop` was
  // requested (false). It does not time out: a device that never finishes holds the caller,
  // whose heartbeat then goes stale, as a hang should (app/service/watchdog.hpp).
  bool wait_for_room(std::stop_token stop);
  // Until every frame handed over is published (true), or as wait_for_room (false).
  bool drain(std::stop_token stop);
  // Hands a submitted frame over; the caller waited for room first.
  void push(std::unique_ptr<Submitted> frame);
  // Handed over and not yet published.
  int on_the_way() const;

 private:
  void loop(std::stop_token stop);
  bool wait_until(std::stop_token stop, int at_most);

  FrameProcessor& processor_;
  StageStats& stats_;
  Publish publish_;
  Fail fail_;
  int capacity_;

  mutable std::mutex mutex_;
  std::condition_variable_any changed_;
  std::deque<std::unique_ptr<Submitted>> queue_;  // handed over, not yet taken; oldest first
  int on_the_way_ = 0;                            // the queue and the frame being finished
  bool stopped_ = false;
  std::jthread thread_;  // last: starts after the members it uses, joined before they go
};

}  // namespace probeless
