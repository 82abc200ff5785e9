#pragma once
// Writes a recording (docs/formats.md "Recording format", version 2). The constructor
// writes calibration.toml, the index headers and then a manifest with `complete = false`;
// each append() writes the frame's images, syncs them (options.sync) and only then appends
// the frame's index line, so a recording killed or cut from power at any point opens with
// every frame before the one in flight (Recording::open() salvages an incomplete one).
// finish() rewrites the manifest with `complete = true` and the frame counts.
//
// The two streams may be appended from two threads (one each); finish() after both stopped.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/calibration.hpp"
#include "core/frame.hpp"
#include "drivers/replay/durable_file.hpp"

namespace probeless::replay {

struct RecordingWriterOptions {
  bool write_truth = true;  // false: frames are recorded without their FrameTruth
  std::string source;       // the source spec, kept in the manifest
  std::string created_by = "probeless";
  // Remove an existing recording in the directory first (only the files a recording has;
  // anything else there still makes the constructor refuse).
  bool overwrite = false;
  // fsync each frame's files and directories, then its index line, before the next frame
  // (docs/formats.md "Power loss"). false: a killed process still loses at most the frame
  // in flight, but a power cut may lose what the kernel had not yet written back.
  bool sync = true;
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
    AppendFile index;
    AppendFile trajectory;  // opened at the first frame with a rig pose
    std::atomic<std::int64_t> count{0};
    TimestampNs first_ns = 0, last_ns = 0;
  };
  // Index fields for a frame's truth ("truth,truth_depth,truth_mask,truth_light,truth_pose").
  std::string write_truth(Stream& stream, const char* trajectory_name, const char* depth_dir,
                          const char* mask_dir, const std::string& name,
                          const std::shared_ptr<const FrameTruth>& truth, TimestampNs t,
                          std::vector<std::string>& written);
  std::string light_file(const std::shared_ptr<const Cubemap>& light);
  // Creates a directory of the recording (and syncs its parent when it is new).
  void create_dir(const std::filesystem::path& rel);
  // Syncs the frame's files and their directories, then appends and syncs its index line.
  void commit(Stream& stream, const std::vector<std::string>& files, const std::string& line);
  void write_manifest(bool complete);

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
