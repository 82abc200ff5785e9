#include "drivers/replay/recording.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "drivers/io/png.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "drivers/replay/light_file.hpp"
#include "drivers/replay/text_fields.hpp"
#include "drivers/replay/tum_trajectory.hpp"

namespace probeless::replay {
namespace {

namespace fs = std::filesystem;

constexpr TimestampNs kFallbackPeriodNs = 33'333'333;  // 30 Hz when a stream has one frame

std::string read_whole_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParseError(path.string(), 0, "cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

int node_line(const toml::node& node) {
  return static_cast<int>(node.source().begin.line);
}

class ManifestReader {
 public:
  ManifestReader(const toml::table& root, std::string source)
      : root_(root), source_(std::move(source)) {}

  const toml::node& require(std::string_view dotted) const {
    const toml::node* node = root_.at_path(dotted).node();
    if (!node) throw ParseError(source_, 0, "missing key '" + std::string(dotted) + "'");
    return *node;
  }
  std::int64_t integer(std::string_view dotted, std::int64_t lo, std::int64_t hi) const {
    const toml::node& node = require(dotted);
    const auto value = node.value_exact<std::int64_t>();
    if (!value) {
      throw ParseError(source_, node_line(node),
                       "'" + std::string(dotted) + "' must be an integer");
    }
    if (*value < lo || *value > hi) {
      throw ParseError(source_, node_line(node),
                       "'" + std::string(dotted) + "' = " + std::to_string(*value) +
                           " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return *value;
  }
  std::string string(std::string_view dotted) const {
    const toml::node& node = require(dotted);
    const auto value = node.value_exact<std::string>();
    if (!value) {
      throw ParseError(source_, node_line(node), "'" + std::string(dotted) + "' must be a string");
    }
    return *value;
  }
  std::string optional_string(std::string_view dotted) const {
    return root_.at_path(dotted).node() ? string(dotted) : std::string();
  }

 private:
  const toml::table& root_;
  std::string source_;
};

RecordingManifest parse_manifest(const fs::path& path) {
  if (!fs::exists(path)) {
    throw ParseError(path.string(), 0,
                     "missing: not a recording (or one interrupted before its first frame, or a "
                     "version-1 recording that was interrupted)");
  }
  const std::string text = read_whole_file(path);
  toml::table root;
  try {
    root = toml::parse(text, path.string());
  } catch (const toml::parse_error& e) {
    throw ParseError(path.string(), static_cast<int>(e.source().begin.line),
                     std::string(e.description()));
  }
  const ManifestReader r(root, path.string());
  RecordingManifest m;
  const std::string format = r.string("format");
  if (format != kRecordingFormatName) {
    throw ParseError(path.string(), node_line(r.require("format")),
                     "format is '" + format + "', expected '" + kRecordingFormatName + "'");
  }
  const toml::node& version = r.require("version");
  const auto v = version.value_exact<std::int64_t>();
  if (!v) throw ParseError(path.string(), node_line(version), "'version' must be an integer");
  if (*v < kOldestRecordingFormatVersion || *v > kRecordingFormatVersion) {
    throw ParseError(path.string(), node_line(version),
                     "unsupported recording version " + std::to_string(*v) +
                         " (this build reads versions " +
                         std::to_string(kOldestRecordingFormatVersion) + " to " +
                         std::to_string(kRecordingFormatVersion) + ")");
  }
  m.version = *v;
  if (m.version >= 2) {  // version 1 wrote its manifest only when complete
    const toml::node& complete = r.require("complete");
    const auto c = complete.value_exact<bool>();
    if (!c) throw ParseError(path.string(), node_line(complete), "'complete' must be a boolean");
    m.complete = *c;
  }
  m.created_utc = r.optional_string("created.utc");
  m.created_by = r.optional_string("created.by");
  m.source = r.optional_string("created.source");
  constexpr std::int64_t kMaxFrames = std::int64_t{1} << 40;
  if (m.complete) {  // an incomplete recording's counts are what its indexes hold
    m.rgbd_frames = r.integer("rgbd.frames", 0, kMaxFrames);
    m.fisheye_frames = r.integer("fisheye.frames", 0, kMaxFrames);
  }
  return m;
}

// A file an index names: relative, inside the recording, and present.
std::string checked_file(const fs::path& dir, std::string_view field, const TextLocation& where,
                         std::string_view column) {
  if (field.empty()) where.fail("empty " + std::string(column) + " file name");
  const fs::path rel(field);
  if (rel.is_absolute() || std::find(rel.begin(), rel.end(), fs::path("..")) != rel.end()) {
    where.fail(std::string(column) + " '" + std::string(field) +
               "' must be a relative path inside the recording");
  }
  if (!fs::is_regular_file(dir / rel)) {
    where.fail("missing file '" + std::string(field) + "' (" + std::string(column) + ")");
  }
  return std::string(field);
}

std::string optional_file(const fs::path& dir, std::string_view field, const TextLocation& where,
                          std::string_view column) {
  return field.empty() ? std::string() : checked_file(dir, field, where, column);
}

bool parse_flag(std::string_view field, const TextLocation& where, std::string_view column) {
  if (field == "1") return true;
  if (field == "0") return false;
  where.fail("bad " + std::string(column) + " '" + std::string(field) + "' (expected 0 or 1)");
}

// The truth columns: truth, truth_depth, truth_mask, truth_light, truth_pose.
TruthEntry parse_truth(const fs::path& dir, const std::vector<std::string_view>& f,
                       std::size_t first, const TextLocation& where, bool* wants_pose) {
  TruthEntry t;
  t.present = parse_flag(f[first], where, "truth");
  *wants_pose = parse_flag(f[first + 4], where, "truth_pose");
  if (!t.present) {
    if (!f[first + 1].empty() || !f[first + 2].empty() || !f[first + 3].empty() || *wants_pose) {
      where.fail("truth columns filled but truth = 0");
    }
    return t;
  }
  t.depth = optional_file(dir, f[first + 1], where, "truth_depth");
  t.mask = optional_file(dir, f[first + 2], where, "truth_mask");
  t.light = optional_file(dir, f[first + 3], where, "truth_light");
  return t;
}

// Lines of an index after its header, with their 1-based numbers; empty lines are skipped.
// `complete_lines_only`: a last line without "\n" (the frame in flight) is left out.
template <typename Row>
void for_each_row(const fs::path& path, const char* header, std::size_t columns,
                  bool complete_lines_only, Row&& row) {
  const std::vector<std::string> lines = read_text_lines(path, complete_lines_only);
  if (lines.empty() || lines.front() != header) {
    throw ParseError(path.string(), 1,
                     std::string("unexpected header (expected '") + header + "')");
  }
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const TextLocation where{path.string(), static_cast<int>(i + 1)};
    const auto fields = split_fields(lines[i], ',');
    if (fields.size() != columns) {
      where.fail("expected " + std::to_string(columns) + " comma-separated fields, got " +
                 std::to_string(fields.size()));
    }
    row(fields, where);
  }
}

// Fills rig_pose of the entries that want one, in order, from a TUM trajectory whose lines
// correspond one to one (same timestamps). An incomplete recording's trajectory may hold
// poses past the last indexed frame (written before its index line): they are ignored.
template <typename Entry>
void attach_poses(const fs::path& dir, const char* file, std::vector<Entry>& entries,
                  const std::vector<std::size_t>& wanting, const char* index_name,
                  bool incomplete) {
  if (wanting.empty()) return;
  const fs::path path = dir / file;
  if (!fs::exists(path)) {
    throw ParseError(path.string(), 0,
                     "missing, but " + std::string(index_name) + " has frames with truth_pose = 1");
  }
  const std::vector<TumPoseLine> poses = read_tum_trajectory(path, incomplete);
  if (poses.size() != wanting.size() && !(incomplete && poses.size() > wanting.size())) {
    throw ParseError(path.string(), poses.empty() ? 0 : poses.back().line,
                     "has " + std::to_string(poses.size()) + " poses, but " + index_name + " has " +
                         std::to_string(wanting.size()) + " frames with truth_pose = 1");
  }
  for (std::size_t k = 0; k < wanting.size(); ++k) {
    Entry& e = entries[wanting[k]];
    if (poses[k].timestamp_ns != e.timestamp_ns) {
      throw ParseError(path.string(), poses[k].line,
                       "timestamp " + format_seconds(poses[k].timestamp_ns) + " does not match " +
                           index_name + ":" + std::to_string(e.line) + " (" +
                           format_seconds(e.timestamp_ns) + ")");
    }
    e.truth.rig_pose = poses[k].pose;
  }
}

template <typename Entry>
void check_count(const fs::path& index, const std::vector<Entry>& entries, std::int64_t expected) {
  if (static_cast<std::int64_t>(entries.size()) != expected) {
    throw ParseError(index.string(), entries.empty() ? 0 : entries.back().line,
                     "has " + std::to_string(entries.size()) + " frames but manifest.toml says " +
                         std::to_string(expected) + " (recording truncated?)");
  }
}

}  // namespace

std::shared_ptr<const Recording> Recording::open(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw ParseError(dir.string(), 0, "not a directory");
  auto rec = std::make_shared<Recording>();
  rec->dir_ = dir;
  rec->manifest_ = parse_manifest(dir / files::kManifest);
  const bool incomplete = !rec->manifest_.complete;

  rec->calibration_ = load_rig_calibration(dir / files::kCalibration);

  const fs::path rgbd_index = dir / files::kRgbdIndex;
  std::vector<std::size_t> rgbd_poses;
  for_each_row(rgbd_index, kRgbdIndexHeader, 9, incomplete,
               [&](const auto& f, const TextLocation& where) {
                 RgbdEntry e;
                 e.line = where.line;
                 e.sequence = parse_uint64(f[0], where, "sequence");
                 e.timestamp_ns = parse_int64(f[1], where, "timestamp_ns");
                 e.colour = checked_file(dir, f[2], where, "color");
                 e.depth = checked_file(dir, f[3], where, "depth");
                 bool wants_pose = false;
                 e.truth = parse_truth(dir, f, 4, where, &wants_pose);
                 if (wants_pose) rgbd_poses.push_back(rec->rgbd_.size());
                 rec->rgbd_.push_back(std::move(e));
               });
  if (incomplete) rec->manifest_.rgbd_frames = static_cast<std::int64_t>(rec->rgbd_.size());
  check_count(rgbd_index, rec->rgbd_, rec->manifest_.rgbd_frames);
  attach_poses(dir, files::kRgbdTrajectory, rec->rgbd_, rgbd_poses, files::kRgbdIndex, incomplete);

  const fs::path fisheye_index = dir / files::kFisheyeIndex;
  std::vector<std::size_t> fisheye_poses;
  for_each_row(fisheye_index, kFisheyeIndexHeader, 15, incomplete,
               [&](const auto& f, const TextLocation& where) {
                 FisheyeEntry e;
                 e.line = where.line;
                 e.sequence = parse_uint64(f[0], where, "sequence");
                 e.timestamp_ns = parse_int64(f[1], where, "timestamp_ns");
                 e.raw = checked_file(dir, f[2], where, "raw");
                 e.bit_depth = static_cast<int>(parse_int_in(f[3], 1, 16, where, "bit_depth"));
                 e.black_level =
                     static_cast<std::uint16_t>(parse_int_in(f[4], 0, 65535, where, "black_level"));
                 e.exposure.exposure.time_s = parse_double(f[5], where, "exposure_time_s");
                 if (e.exposure.exposure.time_s < 0) where.fail("negative exposure_time_s");
                 e.exposure.exposure.gain_db = parse_double(f[6], where, "gain_db");
                 const std::string_view level = f[7];
                 if (level == "low")
                   e.exposure.level = BracketLevel::Low;
                 else if (level == "medium")
                   e.exposure.level = BracketLevel::Medium;
                 else if (level == "high")
                   e.exposure.level = BracketLevel::High;
                 else if (level == "fixed")
                   e.exposure.level = BracketLevel::Fixed;
                 else
                   where.fail("bad bracket_level '" + std::string(level) +
                              "' (expected low, medium, high or fixed)");
                 e.exposure.cycle_position = static_cast<std::uint32_t>(
                     parse_int_in(f[8], 0, 0xffffffffLL, where, "cycle_position"));
                 e.exposure.cycle = parse_uint64(f[9], where, "cycle");
                 bool wants_pose = false;
                 e.truth = parse_truth(dir, f, 10, where, &wants_pose);
                 if (wants_pose) fisheye_poses.push_back(rec->fisheye_.size());
                 rec->fisheye_.push_back(std::move(e));
               });
  if (incomplete) {
    rec->manifest_.fisheye_frames = static_cast<std::int64_t>(rec->fisheye_.size());
  }
  check_count(fisheye_index, rec->fisheye_, rec->manifest_.fisheye_frames);
  attach_poses(dir, files::kFisheyeTrajectory, rec->fisheye_, fisheye_poses, files::kFisheyeIndex,
               incomplete);
  return rec;
}

TimestampNs Recording::start_ns() const {
  if (rgbd_.empty() && fisheye_.empty()) return 0;
  if (rgbd_.empty()) return fisheye_.front().timestamp_ns;
  if (fisheye_.empty()) return rgbd_.front().timestamp_ns;
  return std::min(rgbd_.front().timestamp_ns, fisheye_.front().timestamp_ns);
}

TimestampNs Recording::loop_span_ns() const {
  TimestampNs last = start_ns();
  if (!rgbd_.empty()) last = std::max(last, rgbd_.back().timestamp_ns);
  if (!fisheye_.empty()) last = std::max(last, fisheye_.back().timestamp_ns);
  TimestampNs period = kFallbackPeriodNs;
  const auto mean_period = [](TimestampNs first, TimestampNs final_ts, std::size_t n) {
    return (final_ts - first) / static_cast<TimestampNs>(n - 1);
  };
  if (rgbd_.size() >= 2) {
    period = mean_period(rgbd_.front().timestamp_ns, rgbd_.back().timestamp_ns, rgbd_.size());
  } else if (fisheye_.size() >= 2) {
    period =
        mean_period(fisheye_.front().timestamp_ns, fisheye_.back().timestamp_ns, fisheye_.size());
  }
  return last - start_ns() + std::max<TimestampNs>(period, 1);
}

FrameLoader::FrameLoader(std::shared_ptr<const Recording> recording)
    : recording_(std::move(recording)) {}

std::shared_ptr<const FrameTruth> FrameLoader::load_truth(const TruthEntry& entry) {
  if (!entry.present) return nullptr;
  auto truth = std::make_shared<FrameTruth>();
  const fs::path& dir = recording_->dir();
  if (!entry.depth.empty()) truth->clean_depth = read_png_depth16(dir / entry.depth);
  if (!entry.mask.empty()) truth->occluder_mask = read_png_gray8(dir / entry.mask);
  if (!entry.light.empty()) {
    if (entry.light != cached_light_name_) {
      cached_light_ = std::make_shared<const Cubemap>(read_light_cubemap(dir / entry.light));
      cached_light_name_ = entry.light;
    }
    truth->light = cached_light_;
  }
  truth->rig_pose = entry.rig_pose;
  return truth;
}

RgbdFrame FrameLoader::load(const RgbdEntry& entry) {
  const fs::path& dir = recording_->dir();
  RgbdFrame frame;
  frame.sequence = entry.sequence;
  frame.timestamp_ns = entry.timestamp_ns;
  frame.colour = read_png_rgb8(dir / entry.colour);
  frame.depth = read_png_depth16(dir / entry.depth);
  frame.truth = load_truth(entry.truth);
  return frame;
}

FisheyeFrame FrameLoader::load(const FisheyeEntry& entry) {
  FisheyeFrame frame;
  frame.sequence = entry.sequence;
  frame.timestamp_ns = entry.timestamp_ns;
  frame.raw = read_png_rgb16(recording_->dir() / entry.raw);
  frame.bit_depth = entry.bit_depth;
  frame.black_level = entry.black_level;
  frame.exposure = entry.exposure;
  frame.truth = load_truth(entry.truth);
  return frame;
}

}  // namespace probeless::replay
