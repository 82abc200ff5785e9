#pragma once
// What the recording writer needs to make a frame durable before it indexes it
// (docs/formats.md "Power loss"): an index file appended one whole line per write(2), and
// fsync of files and of the directories that hold their names. A file written and renamed
// is on the disk only once both the file and its directory are synced (rename(2) is atomic
// for the running system, not across a power cut).
#include <filesystem>
#include <string_view>

#include "base/unique_fd.hpp"

namespace probeless::replay {

// A file opened for appending (created or truncated). Each append() is one write(2) of the
// whole text where the kernel allows, so a killed process leaves whole lines, or a last
// line cut short that readers of an interrupted recording ignore. Throws std::runtime_error
// naming the file on failure.
class AppendFile {
 public:
  AppendFile() = default;
  explicit AppendFile(std::filesystem::path path);
  bool is_open() const { return static_cast<bool>(fd_); }
  void append(std::string_view text);
  void sync();  // fdatasync: the lines appended so far survive a power cut
  void close();

 private:
  std::filesystem::path path_;
  UniqueFd fd_;
};

// fsync of a file written by someone else (a PNG): any descriptor of the file flushes it.
void sync_file(const std::filesystem::path& path);
// fsync of a directory: the names created, renamed or removed in it survive a power cut.
void sync_directory(const std::filesystem::path& dir);

}  // namespace probeless::replay
