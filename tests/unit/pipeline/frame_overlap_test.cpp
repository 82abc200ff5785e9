// FrameProcessor's submit()/finish() (issue #19): with frame N+1 rendered and uploaded while
// frame N is on the device, every frame still comes out with its own content, exactly what
// compose() gives one frame at a time; a third frame on the way is refused; a submit that
// throws leaves the frame in flight before it intact.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "app/pipeline/frame_processor.hpp"
#include "unit/pipeline/frame_path_fixture.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;
using testing::at_truth;
using testing::Fixture;
using testing::kFrames;
using testing::make_fixture;
using testing::QueueGate;

// A frame without a pose: camera only, and the stabiliser starts afresh after it, so two
// runs over the same frames see the same history.
void reset(FrameProcessor& p, const RgbdFrame& frame, StageStats& stats) {
  FrameProcessor::Located lost;
  lost.started = std::chrono::steady_clock::now();
  const CompositeFrame out = p.compose(frame, lost, stats);
  EXPECT_FALSE(out.virtual_depth && out.T_world_camera);
}

template <typename T, int C>
double mean_abs_diff(const Image<T, C>& a, const Image<T, C>& b) {
  EXPECT_EQ(a.elements().size(), b.elements().size());
  double sum = 0;
  for (std::size_t i = 0; i < a.elements().size(); ++i)
    sum += std::abs(static_cast<double>(a.elements()[i]) - static_cast<double>(b.elements()[i]));
  return a.elements().empty() ? 0.0 : sum / static_cast<double>(a.elements().size());
}

int differing_pixels(const ImageF& a, const ImageF& b) {
  int n = 0;
  for (std::size_t i = 0; i < a.elements().size(); ++i) n += a.elements()[i] != b.elements()[i];
  return n;
}

// Output `got` is the same frame as `want`: its sequence, pose, virtual layer, matte and
// composite (the same programs on the same device: equal up to float atomics' order).
void expect_same_frame(const CompositeFrame& got, const CompositeFrame& want, int k) {
  SCOPED_TRACE(::testing::Message() << "frame " << k);
  EXPECT_EQ(got.sequence, want.sequence);
  ASSERT_TRUE(got.T_world_camera && want.T_world_camera);
  EXPECT_TRUE(got.T_world_camera->translation.isApprox(want.T_world_camera->translation));
  ASSERT_TRUE(got.colour && got.alpha && got.virtual_depth);
  EXPECT_EQ(mean_abs_diff(*got.virtual_depth, *want.virtual_depth), 0.0);
  EXPECT_EQ(mean_abs_diff(*got.alpha, *want.alpha), 0.0);
  EXPECT_EQ(mean_abs_diff(*got.colour, *want.colour), 0.0);
}

TEST(FrameOverlap, OverlappedFramesMatchTheSerialOnesInOrder) {
  Fixture f = make_fixture();
  ASSERT_EQ(static_cast<int>(f.frames.size()), kFrames);
  FrameProcessor p(f.config, f.rig.calibration, /*keep_matte=*/true);
  StageStats stats;

  reset(p, f.frames[0], stats);
  std::vector<CompositeFrame> serial;
  for (const auto& frame : f.frames) serial.push_back(p.compose(frame, at_truth(frame), stats));
  // The test has teeth: the camera moved, so a neighbour's layer, compared exactly below,
  // would not pass (the orbit moves the objects' outline by a few hundred pixels a frame).
  for (int k = 1; k < kFrames; ++k)
    EXPECT_GT(differing_pixels(*serial[k].virtual_depth, *serial[k - 1].virtual_depth), 50)
        << "frames " << k - 1 << " and " << k << " drew the objects alike";

  reset(p, f.frames[0], stats);
  std::vector<CompositeFrame> overlapped;
  QueueGate gate(p.compute());
  FrameProcessor::InFlight previous = p.submit(f.frames[0], at_truth(f.frames[0]), stats);
  EXPECT_TRUE(previous.on_device());
  for (int k = 1; k < kFrames; ++k) {
    FrameProcessor::InFlight current = p.submit(f.frames[k], at_truth(f.frames[k]), stats);
    if (k == 1) {
      // Frame 1 was rendered and submitted before the device touched frame 0.
      EXPECT_FALSE(gate.released()) << "a submit waited for the device";
      gate.release();
    }
    overlapped.push_back(p.finish(std::move(previous), stats));
    previous = std::move(current);
  }
  overlapped.push_back(p.finish(std::move(previous), stats));
  ASSERT_EQ(overlapped.size(), serial.size());
  for (int k = 0; k < kFrames; ++k) expect_same_frame(overlapped[k], serial[k], k);
  EXPECT_GT(stats.summaries().count("download"), 0U);
}

// Frames 0 and 1 composed one at a time (what submit() and finish() must give), then the
// processor reset for the same frames to go on the way.
struct TwoComposed {
  Fixture f = make_fixture();
  FrameProcessor p{f.config, f.rig.calibration, /*keep_matte=*/true};
  StageStats stats;
  CompositeFrame want0, want1;
  TwoComposed() {
    reset(p, f.frames[0], stats);
    want0 = p.compose(f.frames[0], at_truth(f.frames[0]), stats);
    want1 = p.compose(f.frames[1], at_truth(f.frames[1]), stats);
    reset(p, f.frames[0], stats);
  }
};

TEST(FrameOverlap, AThirdFrameOnTheWayIsRefusedAndTheTwoStillFinish) {
  TwoComposed two;
  auto& [f, p, stats, want0, want1] = two;
  FrameProcessor::InFlight a = p.submit(f.frames[0], at_truth(f.frames[0]), stats);
  FrameProcessor::InFlight b = p.submit(f.frames[1], at_truth(f.frames[1]), stats);
  EXPECT_THROW(p.submit(f.frames[2], at_truth(f.frames[2]), stats), std::logic_error);
  // A frame without a pose has no device work: it may go on the way beside them.
  FrameProcessor::Located lost;
  FrameProcessor::InFlight c = p.submit(f.frames[2], lost, stats);
  EXPECT_FALSE(c.on_device());
  expect_same_frame(p.finish(std::move(a), stats), want0, 0);
  expect_same_frame(p.finish(std::move(b), stats), want1, 1);
  const CompositeFrame camera = p.finish(std::move(c), stats);
  EXPECT_EQ(camera.sequence, f.frames[2].sequence);
  EXPECT_FALSE(camera.T_world_camera.has_value());
}

TEST(FrameOverlap, AFailingSubmitLeavesTheFrameInFlightIntact) {
  TwoComposed two;
  auto& [f, p, stats, want0, want1] = two;
  FrameProcessor::InFlight a = p.submit(f.frames[0], at_truth(f.frames[0]), stats);
  {
    // Rendered, then refused at the upload (not the calibration's size), a frame that dies
    // right after the throw, as the loop's would while unwinding.
    RgbdFrame wrong;
    wrong.colour = ImageRGB8(320, 240);
    wrong.depth = DepthImage(320, 240);
    EXPECT_THROW(p.submit(wrong, at_truth(f.frames[1]), stats), std::invalid_argument);
  }
  expect_same_frame(p.finish(std::move(a), stats), want0, 0);
  // The failed frame held no slot: two frames may be on the way again.
  FrameProcessor::InFlight b = p.submit(f.frames[1], at_truth(f.frames[1]), stats);
  FrameProcessor::InFlight c = p.submit(f.frames[2], at_truth(f.frames[2]), stats);
  expect_same_frame(p.finish(std::move(b), stats), want1, 1);
  // Dropped unfinished (an exception's unwinding): waits for the device, frees the slot.
  { FrameProcessor::InFlight dropped = std::move(c); }
  FrameProcessor::InFlight d = p.submit(f.frames[3], at_truth(f.frames[3]), stats);
  FrameProcessor::InFlight e = p.submit(f.frames[0], at_truth(f.frames[0]), stats);
  EXPECT_EQ(p.finish(std::move(d), stats).sequence, f.frames[3].sequence);
  EXPECT_EQ(p.finish(std::move(e), stats).sequence, f.frames[0].sequence);
}

}  // namespace
}  // namespace probeless
