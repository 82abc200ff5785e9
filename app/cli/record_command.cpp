// probeless record: a source's two streams to a recording directory (docs/formats.md
// "Recording format"). One thread per stream reads and writes (PNG encoding is the cost, and
// the two streams encode in parallel on two cores); the fisheye thread keeps behind the RGB-D
// one so that the recording spans the same time in both streams.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <condition_variable>
#include <csignal>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>

#include "app/cli/commands.hpp"
#include "app/cli/progress.hpp"
#include "drivers/replay/recording_writer.hpp"
#include "drivers/rig_factory.hpp"

namespace probeless::cli {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr auto kReadTimeout = 100ms;
constexpr auto kStallLimit = 30s;  // no RGB-D frame for this long: give up with an error

struct RecordOptions {
  std::string source = "sim";
  std::int64_t frames = 0;
  bool no_truth = false;
  bool force = false;
  bool no_sync = false;
  std::string dir;
};

// Set by SIGINT/SIGTERM while recording: finish the recording cleanly instead of dying.
std::atomic<bool> g_interrupted{false};
extern "C" void on_stop_signal(int) {
  g_interrupted.store(true);
}

class StopSignals {
 public:
  StopSignals() {
    g_interrupted.store(false);
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

// What the two stream threads share.
struct Shared {
  std::mutex mutex;
  std::condition_variable changed;
  TimestampNs rgbd_last_ns = std::numeric_limits<TimestampNs>::min();
  bool rgbd_done = false;
  std::atomic<bool> stop{false};
  std::exception_ptr error;

  void fail(std::exception_ptr e) {
    std::lock_guard lock(mutex);
    if (!error) error = std::move(e);
    stop = true;
    changed.notify_all();
  }
};

std::string read_failure(const std::string& source, SourceState state, const std::string& error) {
  return fmt::format("{}: read failed ({}){}{}", source, to_string(state),
                     error.empty() ? "" : ": ", error);
}

void record_rgbd(RgbdSource& source, replay::RecordingWriter& writer, std::int64_t limit,
                 Shared& shared) {
  RgbdFrame frame;
  auto last_frame = std::chrono::steady_clock::now();
  while (!shared.stop && (limit <= 0 || writer.rgbd_frames() < limit)) {
    const ReadResult r = source.read(frame, kReadTimeout);
    if (r == ReadResult::EndOfStream) break;
    if (r == ReadResult::Error) {
      throw CommandError(read_failure(source.name(), source.state(), source.last_error()));
    }
    if (r == ReadResult::NoFrameYet) {
      if (std::chrono::steady_clock::now() - last_frame > kStallLimit) {
        throw CommandError(fmt::format("{}: no RGB-D frame for {} s (state: {})", source.name(),
                                       kStallLimit.count(), to_string(source.state())));
      }
      continue;
    }
    last_frame = std::chrono::steady_clock::now();
    writer.append(frame);
    std::lock_guard lock(shared.mutex);
    shared.rgbd_last_ns = frame.timestamp_ns;
    shared.changed.notify_all();
  }
}

// Records fisheye frames up to the time of the last RGB-D frame recorded.
void record_fisheye(FisheyeSource& source, replay::RecordingWriter& writer, Shared& shared) {
  std::optional<FisheyeFrame> pending;
  FisheyeFrame frame;
  while (!shared.stop) {
    if (!pending) {
      const ReadResult r = source.read(frame, kReadTimeout);
      if (r == ReadResult::EndOfStream) return;
      if (r == ReadResult::Error) {
        throw CommandError(read_failure(source.name(), source.state(), source.last_error()));
      }
      if (r == ReadResult::NoFrameYet) {
        std::lock_guard lock(shared.mutex);
        if (shared.rgbd_done) return;
        continue;
      }
      pending = std::move(frame);
    }
    std::unique_lock lock(shared.mutex);
    shared.changed.wait(lock, [&] {
      return shared.stop || shared.rgbd_done || pending->timestamp_ns <= shared.rgbd_last_ns;
    });
    if (shared.stop) return;
    if (pending->timestamp_ns > shared.rgbd_last_ns) return;  // RGB-D done: past its end
    lock.unlock();
    writer.append(*pending);
    pending.reset();
  }
}

// Runs `body` on a thread; an exception stops the recording and is kept for the caller.
std::thread stream_thread(Shared& shared, std::function<void()> body) {
  return std::thread([&shared, body = std::move(body)] {
    try {
      body();
    } catch (...) {
      shared.fail(std::current_exception());
    }
  });
}

void check_target(const RecordOptions& o) {
  const fs::path dir(o.dir);
  if (!fs::exists(dir)) return;
  if (!fs::is_directory(dir)) throw CommandError(o.dir + ": exists and is not a directory");
  if (!fs::is_empty(dir) && !o.force) {
    throw CommandError(o.dir +
                       ": directory is not empty (use --force to replace a recording there)");
  }
}

void run_record(const RecordOptions& o) {
  check_target(o);
  Rig rig = open_rig(o.source);
  if (!rig.rgbd) throw CommandError(o.source + ": the source has no RGB-D stream");

  replay::RecordingWriterOptions wo;
  wo.write_truth = !o.no_truth;
  wo.source = o.source;
  wo.created_by = "probeless record";
  wo.overwrite = o.force;
  wo.sync = !o.no_sync;
  replay::RecordingWriter writer(o.dir, rig.calibration, wo);
  spdlog::info("recording {} to {}{}", o.source, o.dir,
               o.frames > 0 ? fmt::format(" ({} RGB-D frames)", o.frames)
                            : " (until the source ends or Ctrl-C)");

  Shared shared;
  StopSignals signals;
  std::thread rgbd = stream_thread(shared, [&] {
    record_rgbd(*rig.rgbd, writer, o.frames, shared);
    std::lock_guard lock(shared.mutex);
    shared.rgbd_done = true;
    shared.changed.notify_all();
  });
  std::thread fisheye;
  if (rig.fisheye) {
    fisheye = stream_thread(shared, [&] { record_fisheye(*rig.fisheye, writer, shared); });
  }

  ProgressBar progress("record", o.frames);
  while (true) {
    {
      std::unique_lock lock(shared.mutex);
      shared.changed.wait_for(lock, 100ms);
      if (g_interrupted && !shared.stop) {
        shared.stop = true;  // finish what is there
        shared.changed.notify_all();
      }
      if (shared.rgbd_done || shared.stop) break;
    }
    progress.update(writer.rgbd_frames(), fmt::format("fisheye {}", writer.fisheye_frames()));
  }
  rgbd.join();
  if (fisheye.joinable()) fisheye.join();
  progress.update(writer.rgbd_frames(), fmt::format("fisheye {}", writer.fisheye_frames()));
  progress.finish();
  // The manifest keeps `complete = false`: the frames written so far still replay.
  if (shared.error) std::rethrow_exception(shared.error);

  writer.finish();
  std::cout << fmt::format("{}: {} RGB-D frames, {} fisheye frames{}\n", o.dir,
                           writer.rgbd_frames(), writer.fisheye_frames(),
                           g_interrupted ? " (stopped by signal)" : "");
}

}  // namespace

void add_record_command(CLI::App& app) {
  auto options = std::make_shared<RecordOptions>();
  CLI::App* cmd = app.add_subcommand(
      "record", "Record a source's RGB-D and fisheye frames to a directory (docs/formats.md)");
  cmd->add_option("--source", options->source, "Source to record: " + rig_spec_help())
      ->capture_default_str();
  cmd->add_option("--frames", options->frames,
                  "RGB-D frames to record; fisheye frames up to the same time (0: until the "
                  "source ends or Ctrl-C)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("--no-truth", options->no_truth, "Leave out the frames' ground truth");
  cmd->add_flag("--force", options->force, "Replace a recording already in DIR");
  cmd->add_flag("--no-sync", options->no_sync,
                "Do not fsync each frame before indexing it: faster on slow storage; a killed "
                "process still loses at most the frame in flight, a power cut more "
                "(docs/formats.md \"Power loss\")");
  cmd->add_option("DIR", options->dir, "Directory to write (created; must be empty)")->required();
  cmd->callback([options] { run_record(*options); });
}

}  // namespace probeless::cli
