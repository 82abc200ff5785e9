#include "drivers/replay/tum_trajectory.hpp"

#include "drivers/replay/text_fields.hpp"

namespace probeless::replay {

std::vector<TumPoseLine> read_tum_trajectory(const std::filesystem::path& path,
                                             bool complete_lines_only) {
  const std::vector<std::string> lines = read_text_lines(path, complete_lines_only);
  std::vector<TumPoseLine> poses;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const TextLocation where{path.string(), static_cast<int>(i + 1)};
    const auto fields = split_whitespace(lines[i]);
    if (fields.empty() || fields.front().front() == '#') continue;
    if (fields.size() != 8) {
      where.fail("expected 8 fields 'timestamp tx ty tz qx qy qz qw', got " +
                 std::to_string(fields.size()));
    }
    TumPoseLine p;
    p.line = where.line;
    p.timestamp_ns = parse_seconds(fields[0], where);
    p.pose.translation = {parse_double(fields[1], where, "tx"),
                          parse_double(fields[2], where, "ty"),
                          parse_double(fields[3], where, "tz")};
    const double qx = parse_double(fields[4], where, "qx");
    const double qy = parse_double(fields[5], where, "qy");
    const double qz = parse_double(fields[6], where, "qz");
    const double qw = parse_double(fields[7], where, "qw");
    if (qx == 0 && qy == 0 && qz == 0 && qw == 0) where.fail("zero quaternion");
    p.pose.rotation = Eigen::Quaterniond(qw, qx, qy, qz);
    poses.push_back(p);
  }
  return poses;
}

std::string format_tum_pose(TimestampNs timestamp_ns, const Pose& pose) {
  const Eigen::Vector3d& t = pose.translation;
  const Eigen::Quaterniond& q = pose.rotation;
  std::string line = format_seconds(timestamp_ns);
  for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
    line += ' ';
    line += format_double(v);
  }
  line += '\n';
  return line;
}

}  // namespace probeless::replay
