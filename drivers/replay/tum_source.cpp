#include "drivers/replay/tum_source.hpp"

#include <algorithm>
#include <fstream>
#include <numeric>
#include <sstream>
#include <tuple>

#include "core/capture_stamp.hpp"
#include "core/error.hpp"
#include "drivers/io/png.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "drivers/replay/text_fields.hpp"
#include "drivers/replay/tum_trajectory.hpp"

namespace probeless::replay {
namespace {

namespace fs = std::filesystem;

std::vector<std::size_t> order_by_time(const std::vector<TimestampNs>& t) {
  std::vector<std::size_t> order(t.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](auto i, auto j) { return t[i] < t[j]; });
  return order;
}

Trajectory load_ground_truth(const fs::path& path) {
  std::vector<TumPoseLine> lines = read_tum_trajectory(path);
  std::stable_sort(lines.begin(), lines.end(),
                   [](const auto& x, const auto& y) { return x.timestamp_ns < y.timestamp_ns; });
  Trajectory trajectory;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i > 0 && lines[i].timestamp_ns == lines[i - 1].timestamp_ns) {
      throw ParseError(path.string(), lines[i].line,
                       "duplicate timestamp " + format_seconds(lines[i].timestamp_ns));
    }
    Pose pose = lines[i].pose;
    pose.rotation.normalize();  // TUM writes quaternions with four decimals
    trajectory.append(lines[i].timestamp_ns, pose);
  }
  return trajectory;
}

RigCalibration tum_default_calibration() {
  RigCalibration c;
  c.rgb = PinholeCamera(PinholeIntrinsics{640, 480, 525.0, 525.0, 319.5, 239.5});
  c.fisheye = nullptr;
  c.T_rig_rgb = Pose::identity();
  c.T_rig_fisheye = Pose::identity();
  return c;
}

}  // namespace

std::vector<TumImageLine> read_tum_image_list(const fs::path& path) {
  const fs::path dir = path.parent_path();
  const std::vector<std::string> lines = read_text_lines(path);
  std::vector<TumImageLine> out;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const TextLocation where{path.string(), static_cast<int>(i + 1)};
    const auto fields = split_whitespace(lines[i]);
    if (fields.empty() || fields.front().front() == '#') continue;
    if (fields.size() != 2) {
      where.fail("expected 'timestamp filename', got " + std::to_string(fields.size()) + " fields");
    }
    TumImageLine entry;
    entry.line = where.line;
    entry.timestamp_ns = parse_seconds(fields[0], where);
    entry.file = std::string(fields[1]);
    const fs::path rel(entry.file);
    if (rel.is_absolute() || std::find(rel.begin(), rel.end(), fs::path("..")) != rel.end()) {
      where.fail("'" + entry.file + "' must be a relative path inside the sequence");
    }
    if (!fs::is_regular_file(dir / rel)) where.fail("missing file '" + entry.file + "'");
    out.push_back(std::move(entry));
  }
  return out;
}

std::vector<std::pair<std::size_t, std::size_t>> associate_by_timestamp(
    const std::vector<TimestampNs>& a, const std::vector<TimestampNs>& b,
    TimestampNs max_difference_ns) {
  const std::vector<std::size_t> b_order = order_by_time(b);
  std::vector<TimestampNs> b_sorted;
  for (std::size_t j : b_order) b_sorted.push_back(b[j]);
  // (|difference|, a time, b time, a index, b index), sorted as associate.py sorts its tuples.
  std::vector<std::tuple<TimestampNs, TimestampNs, TimestampNs, std::size_t, std::size_t>>
      candidates;
  for (std::size_t i = 0; i < a.size(); ++i) {
    auto it = std::upper_bound(b_sorted.begin(), b_sorted.end(), a[i] - max_difference_ns);
    for (; it != b_sorted.end() && *it < a[i] + max_difference_ns; ++it) {
      const std::size_t j = b_order[static_cast<std::size_t>(it - b_sorted.begin())];
      const TimestampNs d = a[i] > b[j] ? a[i] - b[j] : b[j] - a[i];
      if (d < max_difference_ns) candidates.emplace_back(d, a[i], b[j], i, j);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> a_used(a.size()), b_used(b.size());
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  for (const auto& [d, ta, tb, i, j] : candidates) {
    if (a_used[i] || b_used[j]) continue;
    a_used[i] = b_used[j] = true;
    matches.emplace_back(i, j);
  }
  std::stable_sort(matches.begin(), matches.end(),
                   [&](const auto& x, const auto& y) { return a[x.first] < a[y.first]; });
  return matches;
}

DepthImage tum_depth_to_mm(const DepthImage& tum_depth) {
  DepthImage mm(tum_depth.width(), tum_depth.height());
  const auto in = tum_depth.elements();
  auto out = mm.elements();
  // 5000 units per metre = 5 per millimetre; (v + 2) / 5 rounds to nearest.
  for (std::size_t i = 0; i < in.size(); ++i) {
    out[i] = static_cast<std::uint16_t>((static_cast<std::uint32_t>(in[i]) + 2) / 5);
  }
  return mm;
}

TumSequence open_tum_sequence(const fs::path& dir, const fs::path& calibration_file) {
  if (!fs::is_directory(dir)) throw ParseError(dir.string(), 0, "not a directory");
  TumSequence seq;
  seq.dir = dir;
  const std::vector<TumImageLine> rgb = read_tum_image_list(dir / "rgb.txt");
  const std::vector<TumImageLine> depth = read_tum_image_list(dir / "depth.txt");
  std::vector<TimestampNs> rgb_t, depth_t;
  for (const auto& l : rgb) rgb_t.push_back(l.timestamp_ns);
  for (const auto& l : depth) depth_t.push_back(l.timestamp_ns);
  std::optional<Trajectory> truth;
  if (fs::exists(dir / "groundtruth.txt")) truth = load_ground_truth(dir / "groundtruth.txt");
  for (const auto& [i, j] : associate_by_timestamp(rgb_t, depth_t)) {
    TumSequence::Frame f{rgb[i].timestamp_ns, rgb[i].file, depth[j].file, std::nullopt};
    if (truth) f.rig_pose = truth->at(f.timestamp_ns);
    seq.frames.push_back(std::move(f));
  }
  seq.calibration =
      calibration_file.empty() ? tum_default_calibration() : load_rig_calibration(calibration_file);
  return seq;
}

namespace {

Playback make_tum_playback(const TumSequence& seq, const PlaybackOptions& options) {
  std::vector<TimestampNs> timestamps;
  std::vector<std::uint64_t> sequences;
  for (std::size_t i = 0; i < seq.frames.size(); ++i) {
    timestamps.push_back(seq.frames[i].timestamp_ns);
    sequences.push_back(i);
  }
  TimestampNs span = 33'333'333;
  if (timestamps.size() >= 2) {
    const TimestampNs period =
        (timestamps.back() - timestamps.front()) / static_cast<TimestampNs>(timestamps.size() - 1);
    span = timestamps.back() - timestamps.front() + std::max<TimestampNs>(period, 1);
  }
  auto clock = std::make_shared<PlaybackClock>(timestamps.empty() ? 0 : timestamps.front());
  return Playback(std::move(timestamps), std::move(sequences), options, std::move(clock), span);
}

}  // namespace

TumRgbdSource::TumRgbdSource(std::shared_ptr<const TumSequence> sequence, PlaybackOptions options)
    : sequence_(std::move(sequence)), playback_(make_tum_playback(*sequence_, options)) {}

ReadResult TumRgbdSource::read(RgbdFrame& frame, std::chrono::milliseconds timeout) {
  const Playback::Next next = playback_.next(timeout);
  if (next.result != ReadResult::Frame) return next.result;
  const TumSequence::Frame& f = sequence_->frames[next.index];
  try {
    RgbdFrame out;
    out.sequence = next.index + next.sequence_offset;
    out.timestamp_ns = f.timestamp_ns + next.timestamp_offset;
    out.colour = read_png_rgb8(sequence_->dir / f.colour);
    out.depth = tum_depth_to_mm(read_png_depth16(sequence_->dir / f.depth));
    if (playback_.options().stamp) draw_capture_stamp(out.colour, out.timestamp_ns);
    if (out.depth.width() != out.colour.width() || out.depth.height() != out.colour.height()) {
      throw ImageFileError(sequence_->dir / f.depth,
                           "depth is " + std::to_string(out.depth.width()) + "x" +
                               std::to_string(out.depth.height()) + " but colour is " +
                               std::to_string(out.colour.width()) + "x" +
                               std::to_string(out.colour.height()));
    }
    if (f.rig_pose) {
      auto truth = std::make_shared<FrameTruth>();
      truth->rig_pose = f.rig_pose;
      out.truth = std::move(truth);
    }
    frame = std::move(out);
  } catch (const ImageFileError& e) {
    last_error_ = e.what();
    return ReadResult::Error;
  }
  return ReadResult::Frame;
}

Rig open_tum_rig(const fs::path& dir, const PlaybackOptions& options,
                 const fs::path& calibration_file) {
  auto sequence = std::make_shared<const TumSequence>(open_tum_sequence(dir, calibration_file));
  Rig rig;
  rig.calibration = sequence->calibration;
  rig.rgbd = std::make_unique<TumRgbdSource>(sequence, options);
  return rig;
}

}  // namespace probeless::replay
