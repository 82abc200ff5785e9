#pragma once
// The project's recording format (docs/formats.md "Recording format"): a directory with
// manifest.toml (version 2: written first with `complete = false`, rewritten at the end with
// `complete = true` and the frame counts; version 1: written last), calibration.toml,
// one line-based index per stream (rgbd.csv, fisheye.csv), one PNG per image, and, when the
// frames carried ground truth, truth/ and TUM trajectories of the rig pose.
//
// Recording::open() reads and checks everything but the images: a malformed manifest, index
// or trajectory line, or a file an index names but the directory lacks, is a ParseError that
// names the file and line. Images are read per frame (ImageFileError on a bad one).
// A version-2 recording with `complete = false` (interrupted, or still being written) opens
// with the frames its indexes list: a last index or trajectory line cut short is ignored,
// and so are poses and files that no index line names yet.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/calibration.hpp"
#include "core/exposure.hpp"
#include "core/frame.hpp"
#include "core/pose.hpp"
#include "core/time.hpp"

namespace probeless::replay {

inline constexpr const char* kRecordingFormatName = "probeless-recording";
inline constexpr std::int64_t kRecordingFormatVersion = 2;        // what the writer writes
inline constexpr std::int64_t kOldestRecordingFormatVersion = 1;  // readers read 1 and 2

// File names inside a recording directory (fixed by the format).
namespace files {
inline constexpr const char* kManifest = "manifest.toml";
inline constexpr const char* kCalibration = "calibration.toml";
inline constexpr const char* kRgbdIndex = "rgbd.csv";
inline constexpr const char* kFisheyeIndex = "fisheye.csv";
inline constexpr const char* kRgbdTrajectory = "groundtruth.txt";
inline constexpr const char* kFisheyeTrajectory = "fisheye_groundtruth.txt";
}  // namespace files

// Header lines of the indexes; a reader of this version accepts exactly these.
inline constexpr const char* kRgbdIndexHeader =
    "sequence,timestamp_ns,color,depth,truth,truth_depth,truth_mask,truth_light,truth_pose";
inline constexpr const char* kFisheyeIndexHeader =
    "sequence,timestamp_ns,raw,bit_depth,black_level,exposure_time_s,gain_db,bracket_level,"
    "cycle_position,cycle,truth,truth_depth,truth_mask,truth_light,truth_pose";

// Where a frame's ground truth lives; paths are relative to the recording directory and
// empty when absent.
struct TruthEntry {
  bool present = false;
  std::string depth;
  std::string mask;
  std::string light;
  std::optional<Pose> rig_pose;
};

struct RgbdEntry {
  std::uint64_t sequence = 0;
  TimestampNs timestamp_ns = 0;
  std::string colour;
  std::string depth;
  TruthEntry truth;
  int line = 0;  // in rgbd.csv
};

struct FisheyeEntry {
  std::uint64_t sequence = 0;
  TimestampNs timestamp_ns = 0;
  std::string raw;
  int bit_depth = 12;
  std::uint16_t black_level = 0;
  ExposureStamp exposure;
  TruthEntry truth;
  int line = 0;  // in fisheye.csv
};

struct RecordingManifest {
  std::int64_t version = kRecordingFormatVersion;
  // false: the writer never finished (killed, power cut, still recording); the frame counts
  // below are then those salvaged from the indexes.
  bool complete = true;
  std::string created_utc;  // informational
  std::string created_by;
  std::string source;  // the --source spec it was recorded from
  std::int64_t rgbd_frames = 0;
  std::int64_t fisheye_frames = 0;
};

class Recording {
 public:
  // Throws ParseError (manifest, calibration, index and trajectory lines, missing files).
  static std::shared_ptr<const Recording> open(const std::filesystem::path& dir);

  const std::filesystem::path& dir() const { return dir_; }
  const RecordingManifest& manifest() const { return manifest_; }
  const RigCalibration& calibration() const { return calibration_; }
  const std::vector<RgbdEntry>& rgbd() const { return rgbd_; }
  const std::vector<FisheyeEntry>& fisheye() const { return fisheye_; }

  // Earliest timestamp of either stream (the start of replay pacing); 0 when empty.
  TimestampNs start_ns() const;
  // How much one pass advances the timestamps when replay loops: from the first frame of
  // either stream to one mean RGB-D frame period after the last.
  TimestampNs loop_span_ns() const;

 private:
  std::filesystem::path dir_;
  RecordingManifest manifest_;
  RigCalibration calibration_;
  std::vector<RgbdEntry> rgbd_;
  std::vector<FisheyeEntry> fisheye_;
};

// Images of one frame, read from disk. A light cubemap shared by consecutive frames is read
// once and shared (cache holds the last one). Throws ImageFileError.
class FrameLoader {
 public:
  explicit FrameLoader(std::shared_ptr<const Recording> recording);
  RgbdFrame load(const RgbdEntry& entry);
  FisheyeFrame load(const FisheyeEntry& entry);

 private:
  std::shared_ptr<const FrameTruth> load_truth(const TruthEntry& entry);
  std::shared_ptr<const Recording> recording_;
  std::string cached_light_name_;
  std::shared_ptr<const Cubemap> cached_light_;
};

}  // namespace probeless::replay
