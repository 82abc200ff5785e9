#include "drivers/replay/recording_writer.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <sstream>
#include <stdexcept>

#include "drivers/io/png.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "drivers/replay/light_file.hpp"
#include "drivers/replay/recording.hpp"
#include "drivers/replay/text_fields.hpp"
#include "drivers/replay/tum_trajectory.hpp"

namespace probeless::replay {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kLightsRemembered = 4;  // one or two per stream in practice

// Every name a recording may contain at its top level.
constexpr const char* kRecordingEntries[] = {files::kManifest,
                                             files::kCalibration,
                                             files::kRgbdIndex,
                                             files::kFisheyeIndex,
                                             files::kRgbdTrajectory,
                                             files::kFisheyeTrajectory,
                                             "rgb",
                                             "depth",
                                             "fisheye",
                                             "truth",
                                             "manifest.toml.tmp",
                                             "calibration.toml.tmp"};

std::string frame_name(std::int64_t index, const char* extension) {
  return fmt::format("{:06d}.{}", index, extension);
}

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

std::string toml_string(const std::string& text) {
  std::ostringstream out;
  out << toml::value<std::string>(text);
  return out.str();
}

// Through NAME.tmp and rename; with `sync`, the file and then its directory are synced, so
// the new content (not a torn or empty file) is what a power cut leaves.
void write_text_file_atomically(const fs::path& path, const std::string& text, bool sync) {
  fs::path tmp = path;
  tmp += ".tmp";
  {
    AppendFile out(tmp);
    out.append(text);
    if (sync) out.sync();
    out.close();
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(path.string() + ": cannot rename from .tmp: " + ec.message());
  if (sync) sync_directory(path.parent_path());
}

void create_dirs(const fs::path& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) throw std::runtime_error(path.string() + ": cannot create directory: " + ec.message());
}

}  // namespace

void remove_recording_files(const fs::path& dir) {
  for (const char* name : kRecordingEntries) {
    std::error_code ec;
    fs::remove_all(dir / name, ec);
    if (ec) throw std::runtime_error((dir / name).string() + ": cannot remove: " + ec.message());
  }
}

RecordingWriter::RecordingWriter(fs::path dir, const RigCalibration& calibration,
                                 RecordingWriterOptions options)
    : dir_(std::move(dir)), options_(std::move(options)) {
  if (fs::exists(dir_)) {
    if (!fs::is_directory(dir_)) throw std::runtime_error(dir_.string() + ": not a directory");
    if (options_.overwrite) remove_recording_files(dir_);
    if (!fs::is_empty(dir_)) {
      const fs::path first = fs::directory_iterator(dir_)->path();
      throw std::runtime_error(
          dir_.string() + ": directory is not empty (it holds " + first.filename().string() +
          (options_.overwrite ? ", which is not part of a recording)"
                              : "); choose another directory or overwrite it"));
    }
  }
  const bool new_dir = !fs::exists(dir_);
  create_dirs(dir_);
  if (new_dir && options_.sync) {
    fs::path absolute = fs::absolute(dir_);
    if (absolute.filename().empty()) absolute = absolute.parent_path();  // "DIR/"
    sync_directory(absolute.parent_path());
  }
  for (const char* sub : {"rgb", "depth", "fisheye"}) create_dirs(dir_ / sub);
  std::string calibration_text;
  try {
    calibration_text = to_toml(self_contained(calibration));
  } catch (const std::exception& e) {
    throw std::runtime_error(dir_.string() + ": cannot record the rig calibration: " + e.what());
  }
  write_text_file_atomically(dir_ / files::kCalibration, calibration_text, options_.sync);
  rgbd_.index = AppendFile(dir_ / files::kRgbdIndex);
  rgbd_.index.append(std::string(kRgbdIndexHeader) + '\n');
  fisheye_.index = AppendFile(dir_ / files::kFisheyeIndex);
  fisheye_.index.append(std::string(kFisheyeIndexHeader) + '\n');
  if (options_.sync) {
    rgbd_.index.sync();
    fisheye_.index.sync();
  }
  // Last: a directory with a manifest has everything a recording of no frames has.
  write_manifest(false);
}

// Unfinished: the manifest keeps `complete = false`, and readers salvage the frames indexed.
RecordingWriter::~RecordingWriter() = default;

void RecordingWriter::create_dir(const fs::path& rel) {
  const fs::path path = dir_ / rel;
  if (fs::is_directory(path)) return;
  create_dirs(path);
  if (options_.sync) sync_directory(path.parent_path());
}

std::string RecordingWriter::light_file(const std::shared_ptr<const Cubemap>& light) {
  std::lock_guard lock(light_mutex_);
  for (const auto& [known, name] : lights_) {
    if (known == light) return name;
  }
  const std::string name = "truth/light/" + frame_name(light_count_++, "pfm");
  create_dir("truth");
  create_dir("truth/light");
  write_light_cubemap(dir_ / name, *light);
  lights_.emplace_back(light, name);
  if (lights_.size() > kLightsRemembered) lights_.erase(lights_.begin());
  return name;
}

std::string RecordingWriter::write_truth(Stream& stream, const char* trajectory_name,
                                         const char* depth_dir, const char* mask_dir,
                                         const std::string& name,
                                         const std::shared_ptr<const FrameTruth>& truth,
                                         TimestampNs t, std::vector<std::string>& written) {
  if (!options_.write_truth || !truth) return "0,,,,0";
  std::string depth, mask, light;
  if (!truth->clean_depth.empty()) {
    depth = std::string(depth_dir) + "/" + name;
    create_dir("truth");
    create_dir(depth_dir);
    write_png(dir_ / depth, truth->clean_depth);
    written.push_back(depth);
  }
  if (!truth->occluder_mask.empty()) {
    mask = std::string(mask_dir) + "/" + name;
    create_dir("truth");
    create_dir(mask_dir);
    write_png(dir_ / mask, truth->occluder_mask);
    written.push_back(mask);
  }
  if (truth->light) {
    light = light_file(truth->light);
    written.push_back(light);
  }
  if (truth->rig_pose) {
    if (!stream.trajectory.is_open()) {
      stream.trajectory = AppendFile(dir_ / trajectory_name);
      stream.trajectory.append(
          std::string("# rig pose T_world_rig at each frame with truth_pose = 1\n") +
          kTumTrajectoryHeader);
      if (options_.sync) sync_directory(dir_);
    }
    // Before the index line: a pose without its frame (the frame in flight) is ignored by
    // readers of an incomplete recording, a frame without its pose cannot happen.
    stream.trajectory.append(format_tum_pose(t, *truth->rig_pose));
  }
  return "1," + depth + "," + mask + "," + light + "," + (truth->rig_pose ? "1" : "0");
}

void RecordingWriter::commit(Stream& stream, const std::vector<std::string>& written,
                             const std::string& line) {
  if (options_.sync) {
    std::vector<fs::path> dirs;
    for (const std::string& rel : written) {
      sync_file(dir_ / rel);
      const fs::path parent = (dir_ / rel).parent_path();
      if (std::find(dirs.begin(), dirs.end(), parent) == dirs.end()) dirs.push_back(parent);
    }
    for (const fs::path& d : dirs) sync_directory(d);  // the renames from NAME.tmp
    if (stream.trajectory.is_open()) stream.trajectory.sync();
  }
  stream.index.append(line + '\n');
  if (options_.sync) stream.index.sync();
}

void RecordingWriter::append(const RgbdFrame& frame) {
  std::lock_guard lock(rgbd_.mutex);
  if (finished_) throw std::logic_error("RecordingWriter: append after finish");
  const std::int64_t i = rgbd_.count.load();
  const std::string name = frame_name(i, "png");
  std::vector<std::string> written{"rgb/" + name, "depth/" + name};
  write_png(dir_ / written[0], frame.colour);
  write_png(dir_ / written[1], frame.depth);
  const std::string truth = write_truth(rgbd_, files::kRgbdTrajectory, "truth/depth", "truth/mask",
                                        name, frame.truth, frame.timestamp_ns, written);
  commit(rgbd_, written,
         fmt::format("{},{},rgb/{},depth/{},{}", frame.sequence, frame.timestamp_ns, name, name,
                     truth));
  if (i == 0) rgbd_.first_ns = frame.timestamp_ns;
  rgbd_.last_ns = frame.timestamp_ns;
  rgbd_.count.store(i + 1);
}

void RecordingWriter::append(const FisheyeFrame& frame) {
  std::lock_guard lock(fisheye_.mutex);
  if (finished_) throw std::logic_error("RecordingWriter: append after finish");
  const std::int64_t i = fisheye_.count.load();
  const std::string name = frame_name(i, "png");
  std::vector<std::string> written{"fisheye/" + name};
  write_png(dir_ / written[0], frame.raw);
  const std::string truth =
      write_truth(fisheye_, files::kFisheyeTrajectory, "truth/fisheye_depth", "truth/fisheye_mask",
                  name, frame.truth, frame.timestamp_ns, written);
  const ExposureStamp& e = frame.exposure;
  commit(fisheye_, written,
         fmt::format("{},{},fisheye/{},{},{},{},{},{},{},{},{}", frame.sequence, frame.timestamp_ns,
                     name, frame.bit_depth, frame.black_level, format_double(e.exposure.time_s),
                     format_double(e.exposure.gain_db), to_string(e.level), e.cycle_position,
                     e.cycle, truth));
  if (i == 0) fisheye_.first_ns = frame.timestamp_ns;
  fisheye_.last_ns = frame.timestamp_ns;
  fisheye_.count.store(i + 1);
}

void RecordingWriter::finish() {
  std::scoped_lock lock(rgbd_.mutex, fisheye_.mutex);
  if (finished_) return;
  for (Stream* s : {&rgbd_, &fisheye_}) {
    s->index.close();
    if (s->trajectory.is_open()) s->trajectory.close();
  }
  write_manifest(true);
  finished_ = true;
}

void RecordingWriter::write_manifest(bool complete) {
  std::string m;
  m += "# probeless recording (docs/formats.md \"Recording format\"). complete = false: the\n";
  m += "# recording is under way or was interrupted; its indexed frames are all there.\n";
  m += fmt::format("format = {}\nversion = {}\ncomplete = {}\n\n",
                   toml_string(kRecordingFormatName), kRecordingFormatVersion, complete);
  m += fmt::format("[created]\nutc = {}\nby = {}\nhost = {}\nsource = {}\n\n",
                   toml_string(utc_now()), toml_string(options_.created_by),
                   toml_string(host_name()), toml_string(options_.source));
  if (complete) {
    for (const auto& [table, stream] :
         {std::pair{"rgbd", &rgbd_}, std::pair{"fisheye", &fisheye_}}) {
      m += fmt::format("[{}]\nframes = {}\n", table, stream->count.load());
      if (stream->count.load() > 0) {
        m += fmt::format("first_timestamp_ns = {}\nlast_timestamp_ns = {}\n", stream->first_ns,
                         stream->last_ns);
      }
      m += "\n";
    }
  }
  write_text_file_atomically(dir_ / files::kManifest, m, options_.sync);
}

}  // namespace probeless::replay
