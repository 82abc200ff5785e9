// The pipeline's one output loop (app/outputs/output.hpp): every output gets what it asked
// for, and the JPEG is encoded once per frame only while some output wants it.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>

#include "app/pipeline/pipeline.hpp"
#include "drivers/rig_factory.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

// Counts what it was offered; never blocks, as an output must.
class CountingOutput final : public Output {
 public:
  explicit CountingOutput(OutputNeeds needs) : needs_(needs) {}
  std::string_view name() const override { return "counting"; }
  OutputNeeds needs() const override { return needs_; }
  void offer(const OutputFrame& frame) override {
    ++frames;
    if (frame.jpeg && !frame.jpeg->empty()) ++with_jpeg;
    if (frame.colour) ++with_colour;
  }
  void stop() override {}

  std::atomic<int> frames{0}, with_jpeg{0}, with_colour{0};

 private:
  OutputNeeds needs_;
};

ServiceConfig sim_config(int frames) {
  ServiceConfig config;
  config.source = "sim:realtime=0,trajectory=static";
  config.max_frames = frames;
  config.light_enabled = false;
  // A slow sim frame on a loaded machine would otherwise add NO SIGNAL repeats to the count.
  config.no_signal_after_ms = 60'000;
  return config;
}

// Until the output thread has handed out every processed frame.
void run_to_the_end(Pipeline& pipeline) {
  pipeline.start();
  ASSERT_TRUE(pipeline.wait_finished(120s));
  for (int i = 0; i < 5000 && pipeline.frames_out() < pipeline.frames_processed(); ++i)
    std::this_thread::sleep_for(2ms);
  pipeline.stop();
  EXPECT_FALSE(pipeline.fatal_error().has_value()) << pipeline.fatal_error().value_or("");
}

TEST(OutputSeam, WithHttpOffAndPngFilesNoJpegIsEncoded) {
  ServiceConfig config = sim_config(5);
  config.http.enabled = false;
  config.files.dir = testing::scratch_dir() / "frames";
  config.files.format = ImageFileFormat::Png;
  auto colour_only = std::make_shared<CountingOutput>(OutputNeeds{.colour = true});
  PipelineOptions options;
  options.lossless = true;
  options.outputs.push_back(colour_only);
  Pipeline pipeline(config, open_rig(config.source), options);
  run_to_the_end(pipeline);
  EXPECT_EQ(pipeline.frames_out(), 5u);
  EXPECT_EQ(pipeline.jpeg_encodes(), 0u);
  EXPECT_EQ(colour_only->frames, 5);
  EXPECT_EQ(colour_only->with_colour, 5);
  EXPECT_EQ(colour_only->with_jpeg, 0);
  EXPECT_TRUE(std::filesystem::exists(config.files.dir / "frame_000000.png"));
  EXPECT_FALSE(pipeline.status().contains("stages") &&
               pipeline.status()["stages"].contains("encode"));
}

TEST(OutputSeam, TheJpegIsEncodedOncePerFrameForAllThatWantIt) {
  ServiceConfig config = sim_config(5);
  auto a = std::make_shared<CountingOutput>(OutputNeeds{.jpeg = true});
  auto b = std::make_shared<CountingOutput>(OutputNeeds{.jpeg = true, .jpeg_quality = 60});
  auto raw = std::make_shared<CountingOutput>(OutputNeeds{.colour = true});
  PipelineOptions options;
  options.lossless = true;
  options.serve_http = false;  // no port: the two sinks stand in for HTTP clients
  options.outputs = {a, b, raw};
  Pipeline pipeline(config, open_rig(config.source), options);
  run_to_the_end(pipeline);
  EXPECT_EQ(pipeline.frames_out(), 5u);
  EXPECT_EQ(pipeline.jpeg_encodes(), 5u);
  EXPECT_EQ(a->with_jpeg, 5);
  EXPECT_EQ(b->with_jpeg, 5);
  EXPECT_EQ(raw->frames, 5);
  EXPECT_EQ(raw->with_jpeg, 0) << "raw outputs are fed before the encode";
  EXPECT_TRUE(pipeline.status()["stages"].contains("encode"));
}

}  // namespace
}  // namespace probeless
