// FrameFinisher (issue #19's frame p99): a submitted frame is published the moment the device
// has finished it, without waiting for the caller's next frame, in the order handed over, with
// exactly what compose() gives; at most `capacity` frames on the way; a publish that says stop
// stops it. (A failing device is not simulated here: a user event set to an error status
// aborts PoCL 3.1 in pocl_update_event_failed, "PTHREAD ERROR ... Invalid argument".)
#include "app/pipeline/frame_finisher.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "unit/pipeline/frame_path_fixture.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;
using testing::at_truth;
using testing::kFrames;
using testing::make_fixture;
using testing::QueueGate;

// What the finisher published and whether it failed, as the pipeline's callbacks would see.
struct Published {
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<CompositeFrame> frames;
  std::vector<std::string> errors;
  int stop_after = -1;  // publish says stop at this many frames (-1: never)

  FrameFinisher::Publish publish() {
    return [this](CompositeFrame out, const world::LocaliserStatus&, std::stop_token) {
      std::lock_guard lock(mutex);
      frames.push_back(std::move(out));
      changed.notify_all();
      return stop_after < 0 || static_cast<int>(frames.size()) < stop_after;
    };
  }
  FrameFinisher::Fail fail() {
    return [this](const std::string& what) {
      std::lock_guard lock(mutex);
      errors.push_back(what);
      changed.notify_all();
    };
  }
  // Until `n` frames are out or an error came (20 s at most).
  bool wait_for(std::size_t n) {
    std::unique_lock lock(mutex);
    return changed.wait_for(lock, 20s, [&] { return frames.size() >= n || !errors.empty(); }) &&
           frames.size() >= n;
  }
  std::size_t count() {
    std::lock_guard lock(mutex);
    return frames.size();
  }
};

std::unique_ptr<FrameFinisher::Submitted> submitted(FrameProcessor& p, const RgbdFrame& frame,
                                                    StageStats& stats) {
  auto s = std::make_unique<FrameFinisher::Submitted>();
  s->frame = frame;
  s->work = p.submit(s->frame, at_truth(s->frame), stats);
  return s;
}

struct Composed {
  testing::Fixture f = make_fixture();
  FrameProcessor p{f.config, f.rig.calibration, /*keep_matte=*/true};
  StageStats stats;
  std::vector<CompositeFrame> want;  // each frame composed alone, in order
  Composed() {
    for (const auto& frame : f.frames) want.push_back(p.compose(frame, at_truth(frame), stats));
    // The stabiliser starts afresh after a frame without a pose, so the frames submitted next
    // see the same history as the ones composed here.
    FrameProcessor::Located lost;
    lost.started = std::chrono::steady_clock::now();
    p.compose(f.frames[0], lost, stats);
  }
};

void expect_same(const CompositeFrame& got, const CompositeFrame& want, std::size_t k) {
  SCOPED_TRACE(::testing::Message() << "frame " << k);
  EXPECT_EQ(got.sequence, want.sequence);
  ASSERT_TRUE(got.colour && want.colour && got.alpha && want.alpha);
  EXPECT_TRUE(std::ranges::equal(got.colour->elements(), want.colour->elements()));
  EXPECT_TRUE(std::ranges::equal(got.alpha->elements(), want.alpha->elements()));
}

// The frames composed alone, what the finisher publishes, and a finisher over them.
class FrameFinisherTest : public ::testing::Test {
 protected:
  FrameFinisher make(int capacity = kFrameSlots) {
    return FrameFinisher(c.p, c.stats, out.publish(), out.fail(), capacity);
  }
  void push(FrameFinisher& finisher, int k) {
    finisher.push(submitted(c.p, c.f.frames[static_cast<std::size_t>(k)], c.stats));
  }
  Composed c;
  Published out;
};

TEST_F(FrameFinisherTest, AFrameIsPublishedWithoutWaitingForTheNextOne) {
  FrameFinisher finisher = make();
  // The old loop finished frame N only after submitting N+1: here nothing more is submitted.
  push(finisher, 0);
  ASSERT_TRUE(out.wait_for(1)) << "frame 0 never came out on its own";
  expect_same(out.frames[0], c.want[0], 0);
  EXPECT_TRUE(finisher.drain(std::stop_token{}));
  EXPECT_EQ(finisher.on_the_way(), 0);
}

TEST_F(FrameFinisherTest, FramesComeOutInOrderAsComposedAloneAndTheThirdWaitsForRoom) {
  FrameFinisher finisher = make(2);
  QueueGate gate(c.p.compute());
  push(finisher, 0);
  ASSERT_TRUE(finisher.wait_for_room(std::stop_token{}));
  push(finisher, 1);
  EXPECT_EQ(finisher.on_the_way(), 2);
  EXPECT_THROW(push(finisher, 2), std::logic_error);
  // The caller's wait for room lasts while the device holds both frames, and ends with the
  // first one out.
  auto room = std::async(std::launch::async, [&] { return finisher.wait_for_room({}); });
  EXPECT_EQ(room.wait_for(300ms), std::future_status::timeout) << "room while both are held";
  EXPECT_EQ(out.count(), 0U) << "published before the device finished";
  gate.release();
  EXPECT_TRUE(room.get());
  for (std::size_t k = 2; k < static_cast<std::size_t>(kFrames); ++k) {
    ASSERT_TRUE(finisher.wait_for_room(std::stop_token{}));
    push(finisher, static_cast<int>(k));
  }
  ASSERT_TRUE(finisher.drain(std::stop_token{}));
  ASSERT_EQ(out.frames.size(), c.want.size());
  for (std::size_t k = 0; k < out.frames.size(); ++k) expect_same(out.frames[k], c.want[k], k);
  EXPECT_TRUE(out.errors.empty());
}

TEST_F(FrameFinisherTest, APublishThatSaysStopEndsItAndTheRestIsNotPublished) {
  out.stop_after = 1;
  FrameFinisher finisher = make(2);
  QueueGate gate(c.p.compute());
  push(finisher, 0);
  push(finisher, 1);
  gate.release();
  EXPECT_FALSE(finisher.drain(std::stop_token{})) << "a stopped finisher drains nothing more";
  EXPECT_FALSE(finisher.wait_for_room(std::stop_token{}));
  EXPECT_EQ(out.count(), 1U);
}  // the unpublished frame is dropped: it waits for its device work, then goes

TEST_F(FrameFinisherTest, AStopRequestEndsTheWaitForRoom) {
  FrameFinisher finisher = make(1);
  QueueGate gate(c.p.compute());
  push(finisher, 0);
  std::stop_source stop;
  auto room =
      std::async(std::launch::async, [&] { return finisher.wait_for_room(stop.get_token()); });
  EXPECT_EQ(room.wait_for(200ms), std::future_status::timeout);
  stop.request_stop();
  EXPECT_FALSE(room.get());
  gate.release();
  EXPECT_TRUE(out.wait_for(1));
}

TEST_F(FrameFinisherTest, ACapacityBelowOneIsRefused) {
  EXPECT_THROW(make(0), std::invalid_argument);
}

}  // namespace
}  // namespace probeless
