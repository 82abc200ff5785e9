#include "app/outputs/file_output.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
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
  std::filesystem::create_directories(config_.dir);
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
  status["file_output"] = {{"written", s.written},
                           {"dropped", s.dropped},
                           {"failed", s.failed},
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
    std::string error;
    try {
      const std::string name =
          numbered("frame", frame.index, config_.format == ImageFileFormat::Jpeg ? "jpg" : "png");
      if (config_.format == ImageFileFormat::Jpeg) {
        write_file_atomically(config_.dir / name, encoder_.encode(*frame.colour));
      } else {
        write_png(config_.dir / name, *frame.colour);
      }
      if (config_.write_matte) {
        const auto matte_path = config_.dir / numbered("matte", frame.index, "png");
        if (const auto* gray = std::get_if<std::shared_ptr<const ImageGray8>>(&frame.matte)) {
          if (*gray) write_png(matte_path, **gray);
        } else if (const auto* alpha = std::get_if<std::shared_ptr<const ImageF>>(&frame.matte)) {
          if (*alpha) write_png(matte_path, matte_to_gray8(**alpha));
        }
      }
      char line[96];
      std::snprintf(line, sizeof line, "%.6f ", static_cast<double>(frame.timestamp_ns) * 1e-9);
      index_file_ << line << name << '\n' << std::flush;
    } catch (const std::exception& e) {
      error = e.what();
    }
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

}  // namespace probeless
