#pragma once
// Writes a recording (docs/formats.md "Recording format"). Frames are written as they are
// appended, images first and then their index line (flushed), so a crash loses at most the
// frame in flight; finish() writes manifest.toml last, and a directory without it is an
// interrupted recording that Recording::open() refuses.
//
// The two streams may be appended from two threads (one each); finish() after both stopped.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/calibration.hpp"
#include "core/frame.hpp"

namespace probeless::replay {

struct RecordingWriterOptions {
  bool write_truth = true;  // false: frames are recorded without their FrameTruth
  std::string source;       // the source spec, kept in the manifest
  std::string created_by = "probeless";
  // Remove an existing recording in the directory first (only the files a recording has;
  // anything else there still makes the constructor refuse).
  bool overwrite = false;
};

class RecordingWriter {
 public:
  // Creates `dir` (or uses it when empty) and writes calibration.toml. Throws
  // std::runtime_error when the directory is not empty.
  RecordingWriter(std::filesystem::path dir, const RigCalibration& calibration,
                  RecordingWriterOptions options = {});
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  // Throw ImageFileError or std::runtime_error on a write failure.
  void append(const RgbdFrame& frame);
  void append(const FisheyeFrame& frame);
  // Writes the manifest; no appends after it.
  void finish();

  const std::filesystem::path& dir() const { return dir_; }
  std::int64_t rgbd_frames() const { return rgbd_.count.load(); }
  std::int64_t fisheye_frames() const { return fisheye_.count.load(); }

 private:
  struct Stream {
    std::mutex mutex;
    std::ofstream index;
    std::ofstream trajectory;  // opened at the first frame with a rig pose
    std::atomic<std::int64_t> count{0};
    TimestampNs first_ns = 0, last_ns = 0;
  };
  // Index fields for a frame's truth ("truth,truth_depth,truth_mask,truth_light,truth_pose").
  std::string write_truth(Stream& stream, const char* trajectory_name, const char* depth_dir,
                          const char* mask_dir, const std::string& name,
                          const std::shared_ptr<const FrameTruth>& truth, TimestampNs t);
  std::string light_file(const std::shared_ptr<const Cubemap>& light);
  void write_index_line(Stream& stream, const std::string& line, const char* index_name);

  std::filesystem::path dir_;
  RecordingWriterOptions options_;
  Stream rgbd_;
  Stream fisheye_;
  std::mutex light_mutex_;
  // Lights already written (held so that their addresses stay unique), newest last.
  std::vector<std::pair<std::shared_ptr<const Cubemap>, std::string>> lights_;
  int light_count_ = 0;
  bool finished_ = false;
};

// Removes the files and folders a recording consists of from `dir` (nothing else).
void remove_recording_files(const std::filesystem::path& dir);

}  // namespace probeless::replay
