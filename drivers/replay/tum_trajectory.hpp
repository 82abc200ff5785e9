#pragma once
// TUM trajectory files: one pose per line, "timestamp tx ty tz qx qy qz qw", timestamp in
// seconds, '#' comments (https://cvg.cit.tum.de/data/datasets/rgbd-dataset/file_formats).
#include <filesystem>
#include <string>
#include <vector>

#include "core/pose.hpp"
#include "core/time.hpp"

namespace probeless::replay {

struct TumPoseLine {
  TimestampNs timestamp_ns = 0;
  Pose pose;
  int line = 0;  // 1-based line in the file it came from
};

// Values exactly as written (a quaternion is not normalised: recordings replay it bit for
// bit). Throws ParseError naming the file and line for a malformed line.
// `complete_lines_only`: a last line without its "\n" is left out (an interrupted recording).
std::vector<TumPoseLine> read_tum_trajectory(const std::filesystem::path& path,
                                             bool complete_lines_only = false);

// One line (with '\n'), numbers in shortest round-trip form, timestamp with 9 decimals.
std::string format_tum_pose(TimestampNs timestamp_ns, const Pose& pose);

inline constexpr const char* kTumTrajectoryHeader = "# timestamp tx ty tz qx qy qz qw\n";

}  // namespace probeless::replay
