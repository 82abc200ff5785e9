#pragma once
// The composited frames as an image sequence in a directory (`--out DIR`):
// frame_000042.jpg (or .png), matte_000042.png when asked, and frames.txt listing
// "timestamp filename" per written frame in the TUM RGB-D style (seconds on the frames'
// monotonic clock).
//
// Writing runs on its own thread behind a queue of at most `queue_capacity` frames (2): a
// submit() never waits for the disk. When the writer is behind, the oldest waiting frame is
// dropped to make room and counted, so what is written follows the live picture and memory
// stays bounded whatever the disk does. Files appear whole or not at all (written to .tmp,
// then renamed). As a pipeline Output (app/outputs/output.hpp) it writes every frame but the
// NO SIGNAL repeats, numbered in the order offered.
//
// The directory is checked at construction: one that cannot be made or written to (outside
// the unit's StateDirectory under ProtectSystem=strict) is a FileOutputError naming it and
// the fix, so the service stops at start rather than failing frame by frame. Caps bound what
// the directory holds (`[output] max_mb`, `keep_minutes`, `when_full`): the image files of
// this output (frame_*, matte_*, those of earlier runs too) are removed oldest first, or with
// stop_when_full writing stops and /status says why. frames.txt is not capped (~30 bytes a
// frame, 3 MB a day at 30 Hz) and keeps the lines of removed files.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <variant>
#include <vector>

#include "app/outputs/jpeg_encoder.hpp"
#include "app/outputs/output.hpp"
#include "core/image.hpp"
#include "core/time.hpp"

namespace probeless {

enum class ImageFileFormat { Jpeg, Png };

// "jpeg", "jpg" or "png" (the config's output.format); std::invalid_argument otherwise.
ImageFileFormat parse_image_file_format(std::string_view name);

// [output] of the service config (docs/configuration.md) and `run --out DIR`.
struct FileOutputConfig {
  std::filesystem::path dir;  // empty: the service writes no files
  ImageFileFormat format = ImageFileFormat::Jpeg;
  int jpeg_quality = 90;  // files are kept: better than the stream's 80, still ~1/10 of PNG
  bool write_matte = false;
  std::size_t queue_capacity = 2;  // frames waiting for the writer; more only adds latency
  // 0: no cap. At 640x480 JPEG q90 the service writes ~4.6 GB an hour (issue #20).
  std::uint64_t max_bytes = 0;
  std::chrono::minutes max_age{0};  // files older than this are removed; 0: kept
  bool stop_when_full = false;      // at max_bytes: stop writing instead of removing
};

// The directory cannot be made or written to.
class FileOutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct FileOutputFrame {
  std::uint64_t index = 0;  // names the files; gaps show where frames were dropped
  TimestampNs timestamp_ns = 0;
  std::shared_ptr<const ImageRGB8> colour;
  // The matte, written as 8-bit PNG (lossless: a matte is data, JPEG would ring at its
  // edges). A float matte is alpha in [0, 1], stored as round(255 * alpha).
  std::variant<std::monostate, std::shared_ptr<const ImageGray8>, std::shared_ptr<const ImageF>>
      matte;
};

struct FileOutputStats {
  std::uint64_t submitted = 0;
  std::uint64_t written = 0;
  std::uint64_t dropped = 0;  // replaced in the queue before the writer got to them
  std::uint64_t failed = 0;   // write errors (disk full, permissions)
  std::uint64_t removed = 0;  // files removed by the caps
  std::uint64_t bytes = 0;    // what this output's files in the directory hold now
  std::uint64_t files = 0;
  bool full = false;  // stop_when_full and max_bytes reached: nothing more is written
  std::string last_error;
};

ImageGray8 matte_to_gray8(const ImageF& alpha);

class FileOutput final : public Output {
 public:
  // Creates the directory (std::filesystem::filesystem_error on failure) and starts the
  // writer thread.
  explicit FileOutput(FileOutputConfig config);
  ~FileOutput() override;
  FileOutput(const FileOutput&) = delete;
  FileOutput& operator=(const FileOutput&) = delete;
  FileOutput(FileOutput&&) = delete;
  FileOutput& operator=(FileOutput&&) = delete;

  // Queues the frame; returns at once. A frame without colour is ignored.
  void submit(FileOutputFrame frame);
  // Writes what is still queued, then joins the writer. Safe to call twice.
  void stop() override;
  FileOutputStats stats() const;
  const FileOutputConfig& config() const { return config_; }

  // Output: the composite, and the matte with write_matte.
  std::string_view name() const override { return "files"; }
  OutputNeeds needs() const override { return {.colour = true, .matte = config_.write_matte}; }
  void offer(const OutputFrame& frame) override;
  void add_status(nlohmann::json& status) const override;

 private:
  struct Kept {
    std::filesystem::path path;
    std::uint64_t bytes = 0;
    std::filesystem::file_time_type written;
  };
  void run();
  void write(const FileOutputFrame& frame);
  void adopt_existing_files();
  // Records the files just written and applies the caps; the writer thread (and the
  // constructor) only. Returns false when stop_when_full refused the frame.
  bool keep(const std::vector<std::filesystem::path>& written);
  void remove_oldest();

  FileOutputConfig config_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<FileOutputFrame> queue_;
  bool stopping_ = false;
  FileOutputStats stats_;
  std::atomic<std::uint64_t> next_index_{0};  // offer()'s numbering
  JpegEncoder encoder_;       // writer thread only (constructed here to check the quality)
  std::ofstream index_file_;  // frames.txt; writer thread only
  std::deque<Kept> kept_;     // this output's files, oldest first; writer thread only
  std::thread writer_;
};

}  // namespace probeless
