#pragma once
// The TUM RGB-D benchmark layout as a source, as the dataset is downloaded
// (https://cvg.cit.tum.de/data/datasets/rgbd-dataset/file_formats): rgb.txt and depth.txt
// ("timestamp filename" lines, '#' comments), colour PNGs, 16-bit depth PNGs at 5000 units per
// metre, and optionally groundtruth.txt (TUM trajectory). docs/formats.md "TUM RGB-D layout".
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/calibration.hpp"
#include "core/pose.hpp"
#include "drivers/replay/playback.hpp"
#include "drivers/source.hpp"

namespace probeless::replay {

inline constexpr double kTumDepthUnitsPerMetre = 5000.0;
inline constexpr TimestampNs kTumMaxAssociationNs = 20'000'000;  // associate.py's 0.02 s

struct TumImageLine {
  TimestampNs timestamp_ns = 0;
  std::string file;  // relative to the sequence directory
  int line = 0;
};

// Parses rgb.txt / depth.txt; throws ParseError naming the file and line. Files named in it
// must exist.
std::vector<TumImageLine> read_tum_image_list(const std::filesystem::path& path);

// associate.py: candidate pairs closer than `max_difference_ns`, taken greedily from the
// closest, each image used once; the result sorted by colour timestamp. Indices into a and b.
std::vector<std::pair<std::size_t, std::size_t>> associate_by_timestamp(
    const std::vector<TimestampNs>& a, const std::vector<TimestampNs>& b,
    TimestampNs max_difference_ns = kTumMaxAssociationNs);

// TUM depth units (1/5000 m) to millimetres, rounded to nearest; 0 stays 0 (no depth).
DepthImage tum_depth_to_mm(const DepthImage& tum_depth);

struct TumSequence {
  std::filesystem::path dir;
  struct Frame {
    TimestampNs timestamp_ns;  // the colour image's
    std::string colour, depth;
    std::optional<Pose> rig_pose;  // ground truth interpolated at the colour timestamp
  };
  std::vector<Frame> frames;
  RigCalibration calibration;
};

// Reads the lists and the trajectory, associates them. `calibration_file` (TOML, as
// core/calibration.hpp reads it) replaces TUM's default intrinsics (fx = fy = 525,
// cx = 319.5, cy = 239.5, 640x480, no distortion).
TumSequence open_tum_sequence(const std::filesystem::path& dir,
                              const std::filesystem::path& calibration_file = {});

class TumRgbdSource final : public RgbdSource {
 public:
  TumRgbdSource(std::shared_ptr<const TumSequence> sequence, PlaybackOptions options);
  ReadResult read(RgbdFrame& frame, std::chrono::milliseconds timeout) override;
  SourceState state() const override { return playback_.state(); }
  std::string last_error() const override { return last_error_; }
  std::string name() const override { return "tum:" + sequence_->dir.string(); }

 private:
  std::shared_ptr<const TumSequence> sequence_;
  Playback playback_;
  std::string last_error_;
};

// A rig with only the RGB-D stream (TUM has no fisheye).
Rig open_tum_rig(const std::filesystem::path& dir, const PlaybackOptions& options,
                 const std::filesystem::path& calibration_file = {});

}  // namespace probeless::replay
