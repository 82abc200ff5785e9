// The processing loop with frame N+1 rendered while frame N is on the device and finished on
// the finisher's thread (issue #19):
// one output per input, in order, each with its own pose, the last frame of a finite stream
// included, camera-only frames (pose unknown) in their place between frames with device
// work; and an error with frames in flight ends the pipeline cleanly.
#include <gtest/gtest.h>

#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "app/pipeline/pipeline.hpp"
#include "drivers/rig_factory.hpp"
#include "support/pipeline_frames.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

constexpr int kFrames = 9;  // odd: the last frame is alone in flight at the end

// The sim's frames, with the rig pose taken out of some (the "truth" tracker then loses the
// pose: camera-only frames) and, from `shrink_from` on, at another size than the
// calibration's (an error in the frame path).
class EditedSource final : public RgbdSource {
 public:
  EditedSource(std::unique_ptr<RgbdSource> inner, std::set<int> no_pose, int shrink_from)
      : inner_(std::move(inner)), no_pose_(std::move(no_pose)), shrink_from_(shrink_from) {}
  ReadResult read(RgbdFrame& frame, std::chrono::milliseconds timeout) override {
    const ReadResult r = inner_->read(frame, timeout);
    if (r != ReadResult::Frame) return r;
    const int index = count_++;
    if (no_pose_.count(index) && frame.truth) {
      auto truth = std::make_shared<FrameTruth>(*frame.truth);
      truth->rig_pose.reset();
      frame.truth = std::move(truth);
    }
    if (shrink_from_ >= 0 && index >= shrink_from_) {
      frame.colour = ImageRGB8(frame.colour.width() / 2, frame.colour.height() / 2);
      frame.depth = DepthImage(frame.depth.width() / 2, frame.depth.height() / 2);
    }
    return r;
  }
  SourceState state() const override { return inner_->state(); }
  std::string name() const override { return "edited " + inner_->name(); }

 private:
  std::unique_ptr<RgbdSource> inner_;
  std::set<int> no_pose_;
  int shrink_from_;
  int count_ = 0;
};

ServiceConfig truth_config(const std::string& device) {
  ServiceConfig config;
  config.source = "sim:realtime=0,trajectory=orbit,frames=" + std::to_string(kFrames);
  config.tracking.method = "truth";
  // "cpu": the tracker beside the device's work on the frames before; "opencl": its commands
  // on the frame path's queue, behind theirs: both orders are covered.
  config.tracking.device = device;
  config.light_enabled = false;
  config.no_signal_after_ms = 60'000;  // no NO SIGNAL repeats between slow sim frames
  return config;
}

Pipeline make_pipeline(const ServiceConfig& config, std::set<int> no_pose, int shrink_from,
                       Pose& T_rig_rgb, std::vector<std::shared_ptr<Output>> outputs = {}) {
  Rig rig = open_rig(config.source);
  T_rig_rgb = rig.calibration.T_rig_rgb;
  rig.rgbd = std::make_unique<EditedSource>(std::move(rig.rgbd), std::move(no_pose), shrink_from);
  PipelineOptions options;
  options.lossless = true;
  options.keep_matte = true;
  options.serve_http = false;
  options.outputs = std::move(outputs);
  return Pipeline(config, std::move(rig), options);
}

// What the output thread hands the outputs: in lossless mode every frame processed, in the
// order published (the test's own reader of the output slot may miss one under load).
class RecordingOutput final : public Output {
 public:
  std::string_view name() const override { return "recording"; }
  OutputNeeds needs() const override { return {}; }
  void offer(const OutputFrame& frame) override {
    std::lock_guard lock(mutex_);
    frames_.push_back(frame);
  }
  void stop() override {}
  std::vector<OutputFrame> frames() const {
    std::lock_guard lock(mutex_);
    return frames_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<OutputFrame> frames_;
};

class FrameOrder : public ::testing::TestWithParam<std::string> {};

TEST_P(FrameOrder, OneOutputPerInputInOrderWithItsOwnPose) {
  Pose T_rig_rgb;
  auto recording = std::make_shared<RecordingOutput>();
  Pipeline pipeline = make_pipeline(truth_config(GetParam()), {3, 4}, -1, T_rig_rgb, {recording});
  std::vector<CompositeFrame> seen;
  pipeline.start();
  testing::for_each_output_frame(pipeline, [&](const CompositeFrame& f) { seen.push_back(f); });
  for (int i = 0; i < 5000 && pipeline.frames_out() < pipeline.frames_processed(); ++i)
    std::this_thread::sleep_for(2ms);
  pipeline.stop();
  ASSERT_FALSE(pipeline.fatal_error().has_value()) << *pipeline.fatal_error();

  const std::vector<OutputFrame> out = recording->frames();
  ASSERT_EQ(static_cast<int>(out.size()), kFrames) << "one output per input, the last included";
  for (std::size_t k = 0; k < out.size(); ++k) {
    EXPECT_FALSE(out[k].no_signal) << "output " << k;
    if (k > 0) {
      EXPECT_GT(out[k].timestamp_ns, out[k - 1].timestamp_ns) << "output " << k;
    }
  }

  // Each frame the test saw carries the pose of the frame it carries the truth of, and the
  // frames without one (3 and 4) are camera-only in their place.
  ASSERT_FALSE(seen.empty());
  int camera_only = 0;
  for (std::size_t k = 0; k < seen.size(); ++k) {
    SCOPED_TRACE(::testing::Message() << "seen " << k << ", sequence " << seen[k].sequence);
    const CompositeFrame& f = seen[k];
    if (k > 0) {
      EXPECT_GT(f.sequence, seen[k - 1].sequence);
    }
    ASSERT_TRUE(f.truth && f.colour && f.alpha && f.virtual_depth);
    if (!f.truth->rig_pose) {
      EXPECT_FALSE(f.T_world_camera.has_value()) << "a camera-only frame";
      ++camera_only;
      continue;
    }
    ASSERT_TRUE(f.T_world_camera);
    const Pose want = *f.truth->rig_pose * T_rig_rgb;
    EXPECT_LT((f.T_world_camera->translation - want.translation).norm(), 1e-9);
    EXPECT_LT(f.T_world_camera->rotation.angularDistance(want.rotation), 1e-9);
  }
  EXPECT_LE(camera_only, 2);
}

TEST_P(FrameOrder, AnErrorWithFramesInFlightEndsThePipelineCleanly) {
  Pose T_rig_rgb;
  Pipeline pipeline = make_pipeline(truth_config(GetParam()), {}, 5, T_rig_rgb);
  std::vector<std::uint64_t> sequences;
  pipeline.start();
  testing::for_each_output_frame(pipeline,
                                 [&](const CompositeFrame& f) { sequences.push_back(f.sequence); });
  pipeline.stop();
  ASSERT_TRUE(pipeline.fatal_error().has_value());
  EXPECT_NE(pipeline.fatal_error()->find("calibration"), std::string::npos)
      << *pipeline.fatal_error();
  EXPECT_LE(sequences.size(), 5U);
  for (std::size_t k = 1; k < sequences.size(); ++k) EXPECT_EQ(sequences[k], sequences[k - 1] + 1);
}

INSTANTIATE_TEST_SUITE_P(Tracking, FrameOrder, ::testing::Values("cpu", "opencl"));

}  // namespace
}  // namespace probeless
