// The "fire the next exposure" loop: the sequencer sets the camera, the trigger fires, and the
// frame that comes back carries the exposure its pulse was fired for (issue #5: pulses 1:1).
#include "drivers/trigger/exposure_trigger.hpp"

#include <gtest/gtest.h>

#include <chrono>

#include "drivers/bracket/bracket_sequencer.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "drivers/trigger/gpio_trigger.hpp"

namespace probeless {
namespace {

using std::chrono::milliseconds;

TEST(ExposureTrigger, OnePulsePerFrameWithTheFramesExposure) {
  constexpr int kFrames = 200;
  Rig rig = sim::make_sim_rig(
      sim::parse_sim_options("realtime=0,truth=0,fisheye_size=64,trajectory=static,threads=1"));
  BracketSequencer sequencer;
  RecordingTrigger trigger;
  std::vector<ExposureStamp> taken;
  for (int i = 0; i < kFrames; ++i) {
    start_next_frame(sequencer, *rig.fisheye, &trigger);
    FisheyeFrame frame;
    ASSERT_EQ(rig.fisheye->read(frame, milliseconds(5000)), ReadResult::Frame);
    sequencer.observe(frame.exposure,
                      count_exposure(frame.raw, frame.bit_depth, frame.black_level));
    taken.push_back(frame.exposure);
  }
  const std::vector<TriggerPulse> pulses = trigger.pulses();
  ASSERT_EQ(pulses.size(), static_cast<std::size_t>(kFrames));
  const BracketLevel cycle[] = {BracketLevel::Low, BracketLevel::Medium, BracketLevel::High,
                                BracketLevel::Medium};
  for (int i = 0; i < kFrames; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_EQ(pulses[k].exposure, taken[k]) << "frame " << i;
    EXPECT_EQ(pulses[k].exposure.level, cycle[i % 4]) << "frame " << i;
    EXPECT_EQ(pulses[k].exposure.cycle, static_cast<std::uint64_t>(i / 4)) << "frame " << i;
    if (i > 0) {
      EXPECT_GE(pulses[k].time_ns, pulses[k - 1].time_ns);
    }
  }
}

TEST(ExposureTrigger, WithoutATriggerTheCameraIsStillSet) {
  Rig rig = sim::make_sim_rig(sim::parse_sim_options("realtime=0,truth=0,fisheye_size=64"));
  BracketSequencer sequencer;
  const ExposureStamp next = start_next_frame(sequencer, *rig.fisheye, nullptr);
  FisheyeFrame frame;
  ASSERT_EQ(rig.fisheye->read(frame, milliseconds(5000)), ReadResult::Frame);
  EXPECT_EQ(frame.exposure, next);
  EXPECT_EQ(next.level, BracketLevel::Low);
}

// The real line needs a GPIO chip (gpio-sim in the VM tests of issue #7); without one the
// error names what is missing.
TEST(GpioTrigger, MissingChipIsAClearError) {
  GpioTriggerConfig config;
  config.chip = "probeless-no-such-gpiochip";
  try {
    GpioTrigger trigger(config);
    FAIL() << "opened " << trigger.name();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("probeless-no-such-gpiochip"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace probeless
