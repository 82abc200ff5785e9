#include "kernels/runtime/program_binary_cache.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cstring>
#include <fstream>
#include <system_error>

namespace probeless {
namespace {

// File layout: magic, u64 key length, key, u64 binary length, binary, u64 FNV-1a of all of
// the above. Little-endian host order is fine: the key names the device, so a file never
// travels to another architecture and stays valid.
constexpr char kMagic[8] = {'P', 'L', 'C', 'L', 'B', 'I', 'N', '1'};

void put_u64(std::string& out, std::uint64_t v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

bool get_u64(std::string_view& in, std::uint64_t& v) {
  if (in.size() < sizeof v) return false;
  std::memcpy(&v, in.data(), sizeof v);
  in.remove_prefix(sizeof v);
  return true;
}

std::string safe_name(std::string_view name) {
  std::string s;
  for (char c : name.substr(0, 40))
    s += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return s;
}

}  // namespace

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t seed) {
  std::uint64_t h = seed;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::filesystem::path ProgramBinaryCache::path_for(std::string_view name,
                                                   std::string_view key) const {
  return dir_ / fmt::format("{}-{:016x}.clbin", safe_name(name), fnv1a64(key));
}

ProgramBinaryCache::Entry ProgramBinaryCache::load(std::string_view name,
                                                   std::string_view key) const {
  Entry entry;
  const auto path = path_for(name, key);
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return entry;  // Missing
  entry.status = Lookup::Corrupt;
  std::string data(size, '\0');
  std::ifstream f(path, std::ios::binary);
  if (!f.read(data.data(), static_cast<std::streamsize>(size))) return entry;

  std::string_view in = data;
  if (in.size() < sizeof kMagic + sizeof(std::uint64_t)) return entry;
  const std::string_view body = in.substr(0, in.size() - sizeof(std::uint64_t));
  std::string_view tail = in.substr(body.size());
  std::uint64_t checksum = 0;
  get_u64(tail, checksum);
  if (checksum != fnv1a64(body)) return entry;

  in = body;
  if (in.substr(0, sizeof kMagic) != std::string_view(kMagic, sizeof kMagic)) return entry;
  in.remove_prefix(sizeof kMagic);
  std::uint64_t key_len = 0, bin_len = 0;
  if (!get_u64(in, key_len) || key_len > in.size() || in.substr(0, key_len) != key) return entry;
  in.remove_prefix(key_len);
  if (!get_u64(in, bin_len) || bin_len != in.size() || bin_len == 0) return entry;
  entry.binary.assign(in.begin(), in.end());
  entry.status = Lookup::Hit;
  return entry;
}

bool ProgramBinaryCache::store(std::string_view name, std::string_view key,
                               const std::vector<unsigned char>& binary) const {
  std::string data(kMagic, sizeof kMagic);
  put_u64(data, key.size());
  data.append(key);
  put_u64(data, binary.size());
  data.append(reinterpret_cast<const char*>(binary.data()), binary.size());
  put_u64(data, fnv1a64(data));

  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) return false;
  const auto final_path = path_for(name, key);
  // Unique per process and call: two services (or two contexts) may write the same entry.
  static std::atomic<unsigned> counter{0};
  auto tmp = final_path;
  tmp += fmt::format(".tmp.{}.{}", ::getpid(), counter++);
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
  std::filesystem::rename(tmp, final_path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return false;
  }
  return true;
}

void ProgramBinaryCache::remove(std::string_view name, std::string_view key) const {
  std::error_code ec;
  std::filesystem::remove(path_for(name, key), ec);
}

}  // namespace probeless
