#pragma once
// Files that appear whole or not at all, for caches that several processes may write at
// once and that a crash or a full disk may interrupt (the OpenCL program binaries, the PRT
// bakes). The checksummed form also catches what atomicity cannot (a damaged disk, a file
// copied by hand): its last 8 bytes are the FNV-1a (base/hash.hpp) of all before them, in
// host byte order, which is fine for a cache that never leaves its machine.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace probeless {

// `name` (a mesh's, a kernel's) made safe for a cache file's name: its first 40 characters,
// each one that is not a letter, a digit, '-' or '_' replaced by '_'.
std::string file_name_part(std::string_view name);

// Writes `data` to a temporary file beside `path` (creating the directory if needed), then
// renames it over `path`. False, with no temporary left behind, when that fails.
bool write_file_atomically(const std::filesystem::path& path, std::string_view data);

// `body` followed by its checksum, written atomically.
bool write_checksummed_file(const std::filesystem::path& path, std::string body);

struct ChecksummedFile {
  enum class Status {
    Ok,
    Missing,      // no such file (or it cannot be stat'ed)
    Unreadable,   // exists but reading it failed
    Truncated,    // shorter than the checksum plus the smallest body the caller accepts
    BadChecksum,  // torn or damaged
  };
  Status status = Status::Missing;
  std::string body;  // without the checksum; filled only when Ok
};

// Reads a file written by write_checksummed_file(); a body shorter than `min_body` bytes
// (the caller's magic, say) is Truncated.
ChecksummedFile read_checksummed_file(const std::filesystem::path& path, std::size_t min_body = 0);

}  // namespace probeless
