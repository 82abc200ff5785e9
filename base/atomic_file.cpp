#include "base/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <system_error>

#include "base/hash.hpp"

namespace probeless {

std::string file_name_part(std::string_view name) {
  std::string s;
  for (char c : name.substr(0, 40))
    s += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return s;
}

bool write_file_atomically(const std::filesystem::path& path, std::string_view data) {
  std::error_code ec;
  if (path.has_parent_path()) {
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) return false;
  }
  // Unique per process and call: two services (or two threads) may write the same file.
  static std::atomic<unsigned> counter{0};
  auto tmp = path;
  tmp += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(data.data(), static_cast<std::streamsize>(data.size()));
    f.flush();
    if (!f) {
      f.close();
      std::filesystem::remove(tmp, ec);
      return false;
    }
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return false;
  }
  return true;
}

bool write_checksummed_file(const std::filesystem::path& path, std::string body) {
  const std::uint64_t checksum = fnv1a64(body);
  body.append(reinterpret_cast<const char*>(&checksum), sizeof checksum);
  return write_file_atomically(path, body);
}

ChecksummedFile read_checksummed_file(const std::filesystem::path& path, std::size_t min_body) {
  using Status = ChecksummedFile::Status;
  ChecksummedFile file;
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return file;  // Missing
  std::string data(size, '\0');
  std::ifstream f(path, std::ios::binary);
  if (!f.read(data.data(), static_cast<std::streamsize>(size))) {
    file.status = Status::Unreadable;
    return file;
  }
  std::uint64_t checksum = 0;
  if (data.size() < min_body + sizeof checksum) {
    file.status = Status::Truncated;
    return file;
  }
  const std::size_t body_size = data.size() - sizeof checksum;
  std::memcpy(&checksum, data.data() + body_size, sizeof checksum);
  if (checksum != fnv1a64(std::string_view(data).substr(0, body_size))) {
    file.status = Status::BadChecksum;
    return file;
  }
  data.resize(body_size);
  file.body = std::move(data);
  file.status = Status::Ok;
  return file;
}

}  // namespace probeless
