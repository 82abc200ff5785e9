#pragma once
// Program binaries on disk, so that a restart does not pay the OpenCL compiler again (PoCL
// takes ~0.7 s for a small kernel). One file per key; the file repeats the key and carries a
// checksum, so a stale, foreign or torn file is detected and replaced, never trusted.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace probeless {

class ProgramBinaryCache {
 public:
  enum class Lookup { Hit, Missing, Corrupt };
  struct Entry {
    Lookup status = Lookup::Missing;
    std::vector<unsigned char> binary;
  };

  explicit ProgramBinaryCache(std::filesystem::path dir) : dir_(std::move(dir)) {}

  // `key` is the full description of what the binary was built from (docs/opencl.md);
  // `name` only makes the file name readable.
  std::filesystem::path path_for(std::string_view name, std::string_view key) const;
  // Corrupt: unreadable, truncated, wrong magic, another key, or a bad checksum. The caller
  // discards it (remove()) and rebuilds.
  Entry load(std::string_view name, std::string_view key) const;
  // Atomic (base/atomic_file.hpp): written to a temporary file in the same directory, then
  // renamed over. Returns false (and leaves no temporary behind) when the directory is not
  // writable.
  bool store(std::string_view name, std::string_view key,
             const std::vector<unsigned char>& binary) const;
  void remove(std::string_view name, std::string_view key) const;

 private:
  std::filesystem::path dir_;
};

}  // namespace probeless
