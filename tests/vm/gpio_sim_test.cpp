// The GPIO exposure trigger and strobe input against a real kernel driver, gpio-sim (issue #7
// "Tests on real kernel drivers"; docs/gpio.md). Runs inside the VM of tests/vm/run_in_vm.sh
// after check_gpio_sim.sh loaded gpio-sim.ko and made a chip labelled
// $PROBELESS_GPIO_SIM_LABEL with line 0 the trigger, line 1 the strobe and lines 2-3 spare.
// Without that chip it skips, unless PROBELESS_REQUIRE_GPIO_SIM=1 (set in the VM).
//
// The loopback: gpio-sim shows an output line's level in sysfs (sim_gpioN/value) and lets
// userspace pull an input line (sim_gpioN/pull), which raises the line's edge interrupt. A
// triggered-sensor thread (TriggeredSensor) polls the trigger line's value; at each rise it
// latches the exposure it was last given, pulls the strobe line up and delivers one frame;
// when the trigger falls it pulls the strobe down. So a frame and a strobe edge exist only if
// a pulse really appeared on the trigger line, and a frame carries the exposure that was set
// before its pulse.
//
// Polling alone cannot be relied on here: QEMU's vCPU threads share two busy host cores, and
// a vCPU the host does not run for longer than a pulse while the other one runs misses that
// pulse. So the sensor thread and the firing thread share one vCPU, the sensor at SCHED_FIFO
// sleeping kPoll between reads: the line can only change while the firing thread runs,
// which it cannot while the sensor is runnable, and the sensor's timer expires before the
// firing thread's (kPoll < the pulse width, and < the low time between frames). A pulse
// that is never driven, or that ends without a sleep, is still never seen. (A first version,
// free-running and with no low time between frames, missed a pulse within 15 frames: the
// line fell and rose again between two of its reads.)
#include <fcntl.h>
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <latch>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "drivers/bracket/bracket_sequencer.hpp"
#include "drivers/bracket/bracket_simulation.hpp"
#include "drivers/trigger/exposure_trigger.hpp"
#include "drivers/trigger/gpio_chips.hpp"
#include "drivers/trigger/gpio_strobe.hpp"
#include "drivers/trigger/gpio_trigger.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;
constexpr unsigned kTriggerLine = 0, kStrobeLine = 1, kSpareLine = 2, kLines = 4;
// 1 ms pulses and 1 ms low times polled every 100 us: ten reads of each. A real
// sensor's trigger input needs microseconds (GpioTriggerConfig's default is 100 us); under
// TCG a sysfs read alone takes tens of microseconds, so the test uses a longer pulse.
constexpr auto kTestPulse = 1ms;
constexpr auto kPoll = 100us;
// The trigger's low time between frames. A sensor needs one to see the next rising edge; in
// the service it is the frame period less the pulse (~19 ms at 50 fps), here it stands for
// the readout that the test's sensor does not take.
constexpr auto kLowTime = 1ms;
constexpr int kSensorCpu = 0;

// Pins the calling thread to one CPU (and returns the mask it had).
cpu_set_t pin_to_cpu(int cpu) {
  cpu_set_t old;
  CPU_ZERO(&old);
  pthread_getaffinity_np(pthread_self(), sizeof(old), &old);
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(cpu, &one);
  if (pthread_setaffinity_np(pthread_self(), sizeof(one), &one) != 0)
    throw std::runtime_error("cannot pin a thread to CPU " + std::to_string(cpu));
  return old;
}

std::string sim_label() {
  const char* label = std::getenv("PROBELESS_GPIO_SIM_LABEL");
  return label ? label : "";
}

// One sysfs attribute of a gpio-sim line, kept open: pread at offset 0 re-runs its show().
class SimAttribute {
 public:
  SimAttribute(const std::filesystem::path& path, int flags) : path_(path) {
    fd_ = ::open(path.c_str(), flags | O_CLOEXEC);
    if (fd_ < 0) throw std::runtime_error("cannot open " + path.string());
  }
  ~SimAttribute() { ::close(fd_); }
  SimAttribute(const SimAttribute&) = delete;
  SimAttribute& operator=(const SimAttribute&) = delete;

  int read_value() const {
    char c = 0;
    if (::pread(fd_, &c, 1, 0) != 1) throw std::runtime_error("cannot read " + path_.string());
    return c == '1' ? 1 : 0;
  }
  void write(const std::string& text) const {
    if (::pwrite(fd_, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size()))
      throw std::runtime_error("cannot write " + path_.string());
  }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

// The sensor on the far side of the wires, in external-trigger mode: trigger in, strobe and
// frames out. At each rise of the trigger line it latches the exposure it was last given
// (so a trigger fired before set_next_exposure() would take the previous one), pulls the
// strobe up, and delivers one frame taken at the latched exposure (bracket_simulation's
// camera model over a small HDR scene); when the trigger falls it pulls the strobe down.
class TriggeredSensor final : public FisheyeSource {
 public:
  TriggeredSensor(const std::filesystem::path& chip_dir, unsigned trigger, unsigned strobe)
      : trigger_(chip_dir / ("sim_gpio" + std::to_string(trigger)) / "value", O_RDONLY),
        strobe_(chip_dir / ("sim_gpio" + std::to_string(strobe)) / "pull", O_WRONLY),
        model_(SimulatedCameraModel::for_bits(kBits)),
        scene_(32, 32) {
    // 12 stops of radiance, the middle one at 18 % of full scale at the sequencer's start E.
    const double middle =
        0.18 * model_.full_scale() / (BracketConfig{}.initial_exposure * model_.scale);
    const int n = scene_.width() * scene_.height();
    for (int k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c)
        scene_.at(k % scene_.width(), k / scene_.width(), c) =
            static_cast<float>(middle * std::exp2(12.0 * k / (n - 1) - 6.0));
    strobe_.write("pull-down");
    thread_ = std::jthread([this](std::stop_token stop) { run(stop); });
    // Watching before the first pulse: a thread's first run under TCG can come later than a
    // whole pulse.
    ready_.wait();
  }
  ~TriggeredSensor() override {
    thread_.request_stop();
    thread_.join();
  }

  void set_next_exposure(const ExposureStamp& exposure) override {
    std::lock_guard lock(mutex_);
    next_ = exposure;
  }
  ReadResult read(FisheyeFrame& frame, std::chrono::milliseconds timeout) override {
    std::unique_lock lock(mutex_);
    if (!taken_.wait_for(lock, timeout, [&] { return !latched_.empty(); }))
      return ReadResult::NoFrameYet;
    frame.exposure = latched_.front();
    latched_.pop_front();
    lock.unlock();
    frame.sequence = sequence_++;
    frame.timestamp_ns = monotonic_now_ns();  // "end of readout"; the strobe stamp replaces it
    frame.bit_depth = kBits;
    frame.black_level = model_.black_level;
    frame.raw = simulate_capture(scene_, frame.exposure.exposure, model_, rng_);
    return ReadResult::Frame;
  }
  SourceState state() const override { return SourceState::Streaming; }
  std::string name() const override { return "triggered sensor (gpio-sim loopback)"; }

  int pulses_seen() const { return pulses_.load(); }
  long reads() const { return reads_.load(); }

 private:
  static constexpr int kBits = 12;

  void run(std::stop_token stop) {
    pin_to_cpu(kSensorCpu);
    sched_param realtime{};
    realtime.sched_priority = 10;
    if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &realtime) != 0) {
      std::fprintf(stderr, "triggered sensor: cannot run at SCHED_FIFO\n");
      std::abort();  // without it the loopback would be a race with the host's scheduler
    }
    int last = trigger_.read_value();
    ready_.count_down();
    while (!stop.stop_requested()) {
      const int now = trigger_.read_value();
      ++reads_;
      if (now != last) {
        if (now == 1) {
          ++pulses_;
          std::lock_guard lock(mutex_);
          latched_.push_back(next_);
          taken_.notify_one();
        }
        strobe_.write(now == 1 ? "pull-up" : "pull-down");
        last = now;
      }
      std::this_thread::sleep_for(kPoll);
    }
  }

  SimAttribute trigger_;
  SimAttribute strobe_;
  SimulatedCameraModel model_;
  ImageRGBF scene_;
  std::mt19937_64 rng_{7};
  std::uint64_t sequence_ = 0;
  std::mutex mutex_;
  std::condition_variable taken_;
  ExposureStamp next_;
  std::deque<ExposureStamp> latched_;  // taken, not yet read
  std::atomic<int> pulses_{0};
  std::atomic<long> reads_{0};
  std::latch ready_{1};
  std::jthread thread_;
};

// The real trigger, with when each fire() began: the strobe edge of frame i must fall between
// the start of pulse i and the start of pulse i + 1.
class TimedTrigger final : public ExposureTrigger {
 public:
  explicit TimedTrigger(ExposureTrigger& line) : line_(line) {}
  TimestampNs fire(const ExposureStamp& exposure) override {
    const TimestampNs before = monotonic_now_ns();
    const TimestampNs edge = line_.fire(exposure);
    fired_.push_back({exposure, before});
    (void)edge;
    return edge;
  }
  std::string name() const override { return line_.name(); }
  const std::vector<TriggerPulse>& fired() const { return fired_; }

 private:
  ExposureTrigger& line_;
  std::vector<TriggerPulse> fired_;
};

class GpioSim : public ::testing::Test {
 protected:
  void SetUp() override {
    label_ = sim_label();
    if (label_.empty()) {
      const char* require = std::getenv("PROBELESS_REQUIRE_GPIO_SIM");
      if (require != nullptr && std::string(require) == "1")
        FAIL() << "PROBELESS_GPIO_SIM_LABEL is not set";
      GTEST_SKIP() << "no gpio-sim chip (tests/vm/check_gpio_sim.sh runs this in a VM)";
    }
    gpiod::chip chip(label_, gpiod::chip::OPEN_LOOKUP);
    ASSERT_EQ(chip.num_lines(), kLines);
    // /sys/bus/gpio/devices/gpiochipN -> /sys/devices/platform/gpio-sim.M/gpiochipN
    chip_dir_ = std::filesystem::canonical("/sys/bus/gpio/devices/" + chip.name());
  }

  GpioTriggerConfig trigger_config(unsigned line = kTriggerLine) const {
    GpioTriggerConfig c;
    c.chip = label_;
    c.line = line;
    c.pulse_width = kTestPulse;
    return c;
  }
  GpioStrobeConfig strobe_config(unsigned line = kStrobeLine,
                                 StrobeEdge edge = StrobeEdge::Rising) const {
    GpioStrobeConfig c;
    c.chip = label_;
    c.line = line;
    c.edge = edge;
    return c;
  }
  std::filesystem::path attribute(unsigned line, const char* name) const {
    return chip_dir_ / ("sim_gpio" + std::to_string(line)) / name;
  }

  std::string label_;
  std::filesystem::path chip_dir_;
};

// The bar: the trigger pulses match the bracket sequence 1:1 over 200 frames.
TEST_F(GpioSim, TriggerPulsesMatchTheBracketSequenceOneToOneOver200Frames) {
  constexpr int kFrames = 200;
  BracketSequencer sequencer;
  GpioTrigger line(trigger_config());
  TimedTrigger trigger(line);
  GpioStrobe strobe(strobe_config());
  SimAttribute trigger_value(attribute(kTriggerLine, "value"), O_RDONLY);
  ASSERT_EQ(trigger_value.read_value(), 0) << "the trigger must idle inactive";
  // The firing thread on the sensor's vCPU (see the top of the file).
  const cpu_set_t all_cpus = pin_to_cpu(kSensorCpu);
  TriggeredSensor camera(chip_dir_, kTriggerLine, kStrobeLine);

  std::vector<FisheyeFrame> frames;
  std::vector<TimestampNs> seen_by;  // when wait() returned each strobe edge
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < kFrames; ++i) {
    start_next_frame(sequencer, camera, &trigger);
    FisheyeFrame frame;
    ASSERT_EQ(camera.read(frame, 2000ms), ReadResult::Frame)
        << "frame " << i << ": the sensor saw no pulse (" << camera.pulses_seen() << " pulses in "
        << camera.reads() << " reads of the trigger line)";
    // As the pipeline stamps frames, but waiting: the emulated frame needs no readout, so
    // it can be read before the strobe's interrupt has been handled.
    const auto edge = stamp_with_strobe(strobe, frame, 2s);
    ASSERT_TRUE(edge) << "frame " << i << ": no strobe edge within 2 s";
    seen_by.push_back(monotonic_now_ns());
    EXPECT_TRUE(edge->rising) << "frame " << i;
    EXPECT_EQ(frame.timestamp_ns, edge->time_ns) << "frame " << i;
    std::this_thread::sleep_for(kLowTime);
    sequencer.observe(frame.exposure,
                      count_exposure(frame.raw, frame.bit_depth, frame.black_level));
    frames.push_back(std::move(frame));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  pthread_setaffinity_np(pthread_self(), sizeof(all_cpus), &all_cpus);
  EXPECT_FALSE(strobe.wait(100ms)) << "a strobe edge with no pulse behind it";
  EXPECT_EQ(trigger_value.read_value(), 0) << "the trigger must end inactive";

  const auto& fired = trigger.fired();
  ASSERT_EQ(fired.size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(camera.pulses_seen(), kFrames) << "pulses seen on the line in sysfs";
  // The frames' counts steered the sequencer: L and H left their starting 3 stops.
  EXPECT_TRUE(sequencer.low_stop() != -3 || sequencer.high_stop() != 3)
      << sequencer.low_stop() << " " << sequencer.high_stop();
  const BracketLevel cycle[] = {BracketLevel::Low, BracketLevel::Medium, BracketLevel::High,
                                BracketLevel::Medium};
  std::vector<TimestampNs> latency;
  for (int i = 0; i < kFrames; ++i) {
    const auto k = static_cast<std::size_t>(i);
    // The exposure the sensor latched at pulse i is the one set for frame i.
    EXPECT_EQ(fired[k].exposure, frames[k].exposure) << "frame " << i;
    EXPECT_EQ(fired[k].exposure.level, cycle[i % 4]) << "frame " << i;
    EXPECT_EQ(fired[k].exposure.cycle, static_cast<std::uint64_t>(i / 4)) << "frame " << i;
    // The kernel's edge time is CLOCK_MONOTONIC and belongs to this frame's pulse: after
    // fire() began and before wait() returned it (and so before the next pulse).
    EXPECT_GT(frames[k].timestamp_ns, fired[k].time_ns) << "frame " << i;
    EXPECT_LT(frames[k].timestamp_ns, seen_by[k]) << "frame " << i;
    if (i > 0) {
      EXPECT_GT(frames[k].timestamp_ns, frames[k - 1].timestamp_ns) << "frame " << i;
    }
    latency.push_back(frames[k].timestamp_ns - fired[k].time_ns);
  }
  std::sort(latency.begin(), latency.end());
  std::printf(
      "gpio-sim: %d frames, %zu pulses fired, %d seen on the line, %zu strobe edges in "
      "%.2f s; pulse start -> strobe edge median %.2f ms, max %.2f ms\n",
      kFrames, fired.size(), camera.pulses_seen(), frames.size(), seconds,
      static_cast<double>(latency[latency.size() / 2]) * 1e-6,
      static_cast<double>(latency.back()) * 1e-6);
}

// One pull at a time, each edge awaited before the next: the v1 ABI reads the level in its
// interrupt thread to tell a rising from a falling edge, and irq_sim drops an interrupt raised
// while the line's is masked, so back-to-back pulls would test the simulator, not the strobe.
TEST_F(GpioSim, StrobeSeesBothEdgesInOrderWhenAskedTo) {
  GpioStrobe strobe(strobe_config(kSpareLine, StrobeEdge::Both));
  SimAttribute pull(attribute(kSpareLine, "pull"), O_WRONLY);
  std::vector<StrobeEvent> events;
  for (const char* level : {"pull-up", "pull-down", "pull-up"}) {
    pull.write(level);
    const auto e = strobe.wait(1s);
    ASSERT_TRUE(e) << "no edge after " << level;
    events.push_back(*e);
  }
  EXPECT_TRUE(events[0].rising);
  EXPECT_FALSE(events[1].rising);
  EXPECT_TRUE(events[2].rising);
  EXPECT_LT(events[0].time_ns, events[1].time_ns);
  EXPECT_LT(events[1].time_ns, events[2].time_ns);
  pull.write("pull-down");
  std::this_thread::sleep_for(100ms);
  const auto last = strobe.latest();  // drains the queued falling edge
  ASSERT_TRUE(last);
  EXPECT_FALSE(last->rising);
  EXPECT_FALSE(strobe.wait(0ns));
}

TEST_F(GpioSim, RisingStrobeIgnoresFallingEdges) {
  GpioStrobe strobe(strobe_config(kSpareLine, StrobeEdge::Rising));
  SimAttribute pull(attribute(kSpareLine, "pull"), O_WRONLY);
  pull.write("pull-up");
  const auto e = strobe.wait(1s);
  ASSERT_TRUE(e);
  EXPECT_TRUE(e->rising);
  pull.write("pull-down");
  EXPECT_FALSE(strobe.wait(200ms)) << "the falling edge must not be reported";
}

void ignore_signal(int) {}

// The wait is bounded and a signal (SIGUSR1 without SA_RESTART) neither ends it early nor
// turns into an error.
TEST_F(GpioSim, WaitIsBoundedAndRidesOutSignals) {
  struct sigaction action {};
  action.sa_handler = ignore_signal;
  sigemptyset(&action.sa_mask);
  struct sigaction previous {};
  ASSERT_EQ(sigaction(SIGUSR1, &action, &previous), 0);
  GpioStrobe strobe(strobe_config(kSpareLine));
  const pthread_t waiter = pthread_self();
  std::atomic<int> sent{0};
  std::jthread pester([&](std::stop_token stop) {
    while (!stop.stop_requested()) {
      std::this_thread::sleep_for(20ms);
      pthread_kill(waiter, SIGUSR1);
      ++sent;
    }
  });
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<StrobeEvent> e;
  EXPECT_NO_THROW(e = strobe.wait(300ms));
  const auto waited = std::chrono::steady_clock::now() - t0;
  pester.request_stop();
  pester.join();
  sigaction(SIGUSR1, &previous, nullptr);
  EXPECT_FALSE(e);
  EXPECT_GE(waited, 300ms);
  EXPECT_LT(waited, 3s);
  EXPECT_GE(sent.load(), 3) << "the signals must have arrived during the wait";
}

// What `probeless devices` lists: the sim chip with its label, its lines, and the one in use.
TEST_F(GpioSim, ChipListShowsTheSimChipAndItsLinesInUse) {
  GpioStrobe strobe(strobe_config(kSpareLine));
  const auto chips = list_gpio_chips();
  const auto it = std::find_if(chips.begin(), chips.end(),
                               [&](const GpioChipInfo& c) { return c.label == label_; });
  ASSERT_NE(it, chips.end()) << "no chip labelled " << label_;
  EXPECT_TRUE(it->error.empty()) << it->error;
  EXPECT_EQ(it->lines, kLines);
  EXPECT_EQ(it->used, 1u);
  EXPECT_EQ("/sys/bus/gpio/devices/" + it->name,
            "/sys/bus/gpio/devices/" + chip_dir_.filename().string());
}

// The errors a misconfigured board gives, each naming the chip and line.
TEST_F(GpioSim, MissingChipIsAClearError) {
  GpioTriggerConfig t = trigger_config();
  t.chip = "probeless-no-such-chip";
  try {
    GpioTrigger trigger(t);
    FAIL() << "opened " << trigger.name();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'probeless-no-such-chip'"), std::string::npos)
        << e.what();
  }
  GpioStrobeConfig s = strobe_config();
  s.chip = "/dev/gpiochip99";
  try {
    GpioStrobe strobe(s);
    FAIL() << "opened " << strobe.name();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'/dev/gpiochip99'"), std::string::npos) << e.what();
  }
}

TEST_F(GpioSim, LineOutOfRangeIsAClearError) {
  try {
    GpioTrigger trigger(trigger_config(kLines));
    FAIL() << "requested " << trigger.name();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("has 4 lines, no line 4"), std::string::npos) << e.what();
  }
  try {
    GpioStrobe strobe(strobe_config(kLines + 10));
    FAIL() << "requested " << strobe.name();
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(label_), std::string::npos) << what;
    EXPECT_NE(what.find("has 4 lines, no line 14"), std::string::npos) << what;
  }
}

TEST_F(GpioSim, BusyLineIsAClearErrorAndFreedOnDestruction) {
  {
    GpioStrobe first(strobe_config(kSpareLine));
    try {
      GpioStrobe second(strobe_config(kSpareLine));
      FAIL() << "requested " << second.name() << " twice";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(label_ + " line 2"), std::string::npos) << what;
      EXPECT_NE(what.find("busy"), std::string::npos) << what;
      EXPECT_NE(what.find("held by 'probeless-strobe'"), std::string::npos) << what;
    }
    try {
      GpioTrigger trigger(trigger_config(kSpareLine));
      FAIL() << "drove " << trigger.name() << " while it is a strobe input";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(label_ + " line 2"), std::string::npos) << what;
      EXPECT_NE(what.find("busy"), std::string::npos) << what;
    }
  }
  // RAII: the strobe released the line, so the trigger gets it now.
  EXPECT_NO_THROW(GpioTrigger trigger(trigger_config(kSpareLine)));
}

}  // namespace
}  // namespace probeless
