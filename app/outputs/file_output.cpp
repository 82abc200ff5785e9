#include "app/outputs/file_output.hpp"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include "app/outputs/jpeg_encoder.hpp"
#include "drivers/io/png.hpp"

namespace probeless {
namespace {

std::string numbered(const char* prefix, std::uint64_t index, const char* extension) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%06llu.%s", prefix, static_cast<unsigned long long>(index),
                extension);
  return name;
}

// Same convention as write_png: the file appears complete or not at all.
void write_file_atomically(const std::filesystem::path& path, std::span<const std::uint8_t> bytes) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) throw ImageFileError(path, std::generic_category().message(errno));
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int write_errno = errno;
  if (std::fclose(f) != 0 || !written) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw ImageFileError(path, std::generic_category().message(written ? errno : write_errno));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw ImageFileError(path, ec.message());
}

std::string not_writable(const std::filesystem::path& dir, const std::string& why) {
  return "[output] dir " + dir.string() + " is not writable (" + why +
         "): under the systemd unit (ProtectSystem=strict) the service may write only below "
         "/var/lib/probeless; set dir there, or allow this one with ReadWritePaths= in a "
         "drop-in (docs/appliance.md \"Output directory\")";
}

// Creates the directory and a file in it, so a read-only mount shows now, not at the first
// frame.
void check_writable(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw FileOutputError(not_writable(dir, ec.message()));
  const auto probe = dir / ".probeless-write-check";
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0640);
  if (fd < 0) throw FileOutputError(not_writable(dir, std::strerror(errno)));
  ::close(fd);
  ::unlink(probe.c_str());
}

// This output's own files: frame_NNNNNN.jpg|png and matte_NNNNNN.png.
bool is_output_image(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  const std::string ext = path.extension().string();
  return (name.starts_with("frame_") && (ext == ".jpg" || ext == ".png")) ||
         (name.starts_with("matte_") && ext == ".png");
}

std::string megabytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MB", static_cast<double>(bytes) / 1e6);
  return text;
}

}  // namespace

ImageFileFormat parse_image_file_format(std::string_view name) {
  if (name == "jpeg" || name == "jpg") return ImageFileFormat::Jpeg;
  if (name == "png") return ImageFileFormat::Png;
  throw std::invalid_argument("unknown image file format \"" + std::string(name) +
                              "\" (expected jpeg or png)");
}

ImageGray8 matte_to_gray8(const ImageF& alpha) {
  ImageGray8 out(alpha.width(), alpha.height());
  const auto in = alpha.elements();
  auto dst = out.elements();
  for (std::size_t i = 0; i < in.size(); ++i) {
    const float a = std::isnan(in[i]) ? 0.0f : std::fmin(std::fmax(in[i], 0.0f), 1.0f);
    dst[i] = static_cast<std::uint8_t>(std::lround(a * 255.0f));
  }
  return out;
}

FileOutput::FileOutput(FileOutputConfig config)
    : config_(std::move(config)), encoder_(config_.jpeg_quality) {
  if (config_.queue_capacity == 0) config_.queue_capacity = 1;
  check_writable(config_.dir);
  adopt_existing_files();
  index_file_.open(config_.dir / "frames.txt", std::ios::out | std::ios::app);
  if (!index_file_) {
    throw std::filesystem::filesystem_error("cannot open frames.txt", config_.dir / "frames.txt",
                                            std::make_error_code(std::errc::io_error));
  }
  writer_ = std::thread([this] { run(); });
}

FileOutput::~FileOutput() {
  stop();
}

void FileOutput::submit(FileOutputFrame frame) {
  if (!frame.colour) return;
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    ++stats_.submitted;
    if (queue_.size() >= config_.queue_capacity) {
      queue_.pop_front();
      ++stats_.dropped;
    }
    queue_.push_back(std::move(frame));
  }
  wake_.notify_one();
}

void FileOutput::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (writer_.joinable()) writer_.join();
}

void FileOutput::offer(const OutputFrame& frame) {
  if (frame.no_signal) return;  // the files keep what the camera saw
  FileOutputFrame f;
  f.index = next_index_++;
  f.timestamp_ns = frame.timestamp_ns;
  f.colour = frame.colour;
  if (config_.write_matte && frame.matte) f.matte = frame.matte;
  submit(std::move(f));
}

void FileOutput::add_status(nlohmann::json& status) const {
  const auto s = stats();
  status["file_output"] = {{"state", s.full ? "full" : "writing"},
                           {"written", s.written},
                           {"dropped", s.dropped},
                           {"failed", s.failed},
                           {"removed", s.removed},
                           {"bytes", s.bytes},
                           {"files", s.files},
                           {"last_error", s.last_error}};
}

FileOutputStats FileOutput::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void FileOutput::run() {
  for (;;) {
    FileOutputFrame frame;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping, and everything queued is written
      frame = std::move(queue_.front());
      queue_.pop_front();
    }
    {
      std::lock_guard lock(mutex_);
      if (stats_.full) continue;  // the cap said stop: /status says so
    }
    std::string error;
    bool kept = true;
    try {
      const std::string name =
          numbered("frame", frame.index, config_.format == ImageFileFormat::Jpeg ? "jpg" : "png");
      std::vector<std::filesystem::path> written{config_.dir / name};
      if (config_.format == ImageFileFormat::Jpeg) {
        write_file_atomically(written[0], encoder_.encode(*frame.colour));
      } else {
        write_png(written[0], *frame.colour);
      }
      if (config_.write_matte) {
        const auto matte_path = config_.dir / numbered("matte", frame.index, "png");
        if (const auto* gray = std::get_if<std::shared_ptr<const ImageGray8>>(&frame.matte)) {
          if (*gray) {
            write_png(matte_path, **gray);
            written.push_back(matte_path);
          }
        } else if (const auto* alpha = std::get_if<std::shared_ptr<const ImageF>>(&frame.matte)) {
          if (*alpha) {
            write_png(matte_path, matte_to_gray8(**alpha));
            written.push_back(matte_path);
          }
        }
      }
      kept = keep(written);
      if (kept) {
        char line[96];
        std::snprintf(line, sizeof line, "%.6f ", static_cast<double>(frame.timestamp_ns) * 1e-9);
        index_file_ << line << name << '\n' << std::flush;
      }
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (!kept) continue;  // keep() logged and set the status once
    bool new_error = false;
    {
      std::lock_guard lock(mutex_);
      if (error.empty()) {
        ++stats_.written;
      } else {
        ++stats_.failed;
        new_error = error != stats_.last_error;
        stats_.last_error = error;
      }
    }
    // One log line per distinct error, not one per frame at 30 Hz (a full disk stays full).
    if (new_error) spdlog::warn("file output: {}", error);
  }
}

void FileOutput::adopt_existing_files() {
  // Files of earlier runs count against the caps too: the cap is what the disk holds.
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(config_.dir, ec)) {
    if (!entry.is_regular_file(ec) || !is_output_image(entry.path())) continue;
    Kept k{entry.path(), entry.file_size(ec), entry.last_write_time(ec)};
    if (!ec) kept_.push_back(std::move(k));
  }
  std::sort(kept_.begin(), kept_.end(), [](const Kept& a, const Kept& b) {
    return a.written != b.written ? a.written < b.written : a.path < b.path;
  });
  std::uint64_t bytes = 0;
  for (const auto& k : kept_) bytes += k.bytes;
  {
    std::lock_guard lock(mutex_);
    stats_.bytes = bytes;
    stats_.files = kept_.size();
  }
  keep({});
}

void FileOutput::remove_oldest() {
  const Kept oldest = std::move(kept_.front());
  kept_.pop_front();
  std::error_code ec;
  std::filesystem::remove(oldest.path, ec);
  std::lock_guard lock(mutex_);
  stats_.bytes -= std::min(stats_.bytes, oldest.bytes);
  stats_.files = kept_.size();
  ++stats_.removed;
}

bool FileOutput::keep(const std::vector<std::filesystem::path>& written) {
  std::uint64_t added = 0;
  for (const auto& path : written) {
    std::error_code ec;
    Kept k{path, std::filesystem::file_size(path, ec),
           std::filesystem::file_time_type::clock::now()};
    if (ec) k.bytes = 0;
    added += k.bytes;
    kept_.push_back(std::move(k));
  }
  std::uint64_t bytes = 0;
  {
    std::lock_guard lock(mutex_);
    stats_.bytes += added;
    stats_.files = kept_.size();
    bytes = stats_.bytes;
  }
  if (config_.max_age.count() > 0) {
    const auto cutoff = std::filesystem::file_time_type::clock::now() - config_.max_age;
    while (!kept_.empty() && kept_.front().written < cutoff) remove_oldest();
  }
  {
    std::lock_guard lock(mutex_);
    bytes = stats_.bytes;
  }
  if (config_.max_bytes == 0 || bytes <= config_.max_bytes) return true;
  if (!config_.stop_when_full) {
    // Never the frame just written: the newest picture is the one worth keeping.
    while (kept_.size() > written.size() && bytes > config_.max_bytes) {
      remove_oldest();
      std::lock_guard lock(mutex_);
      bytes = stats_.bytes;
    }
    return true;
  }
  // Full: what was just written goes again, so the directory stays under the cap.
  for (std::size_t i = 0; i < written.size(); ++i) {
    std::error_code ec;
    std::filesystem::remove(kept_.back().path, ec);
    added = kept_.back().bytes;
    kept_.pop_back();
    std::lock_guard lock(mutex_);
    stats_.bytes -= std::min(stats_.bytes, added);
  }
  std::string message = "output cap reached: " + megabytes(bytes) + " in " + config_.dir.string() +
                        " against [output] max_mb = " + megabytes(config_.max_bytes) +
                        " with when_full = \"stop\": no more frames are written";
  {
    std::lock_guard lock(mutex_);
    stats_.full = true;
    stats_.files = kept_.size();
    stats_.last_error = message;
  }
  spdlog::warn("file output: {}", message);
  return false;
}

}  // namespace probeless
