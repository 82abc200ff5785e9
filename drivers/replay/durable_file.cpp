#include "drivers/replay/durable_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace probeless::replay {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const char* what) {
  throw std::runtime_error(path.string() + ": " + what + ": " + std::strerror(errno));
}

void sync_path(const std::filesystem::path& path, int flags) {
  UniqueFd fd(::open(path.c_str(), flags | O_CLOEXEC));
  if (!fd) fail(path, "cannot open to sync");
  if (::fsync(fd.get()) != 0) fail(path, "fsync failed");
}

}  // namespace

AppendFile::AppendFile(std::filesystem::path path) : path_(std::move(path)) {
  fd_.reset(::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644));
  if (!fd_) fail(path_, "cannot create");
}

void AppendFile::append(std::string_view text) {
  while (!text.empty()) {
    const ssize_t n = ::write(fd_.get(), text.data(), text.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      fail(path_, "write failed");
    }
    text.remove_prefix(static_cast<std::size_t>(n));
  }
}

void AppendFile::sync() {
  if (::fdatasync(fd_.get()) != 0) fail(path_, "fdatasync failed");
}

void AppendFile::close() {
  const int fd = fd_.release();
  if (fd >= 0 && ::close(fd) != 0 && errno != EINTR) fail(path_, "close failed");
}

void sync_file(const std::filesystem::path& path) {
  sync_path(path, O_RDONLY);
}

void sync_directory(const std::filesystem::path& dir) {
  sync_path(dir, O_RDONLY | O_DIRECTORY);
}

}  // namespace probeless::replay
