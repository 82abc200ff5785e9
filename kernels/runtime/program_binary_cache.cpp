#include "kernels/runtime/program_binary_cache.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <system_error>

#include "base/atomic_file.hpp"
#include "base/hash.hpp"
#include "base/raw_bytes.hpp"

namespace probeless {
namespace {

// File layout: magic, u64 key length, key, u64 binary length, binary, u64 FNV-1a of all of
// the above (base/atomic_file.hpp). Little-endian host order is fine: the key names the
// device, so a file never travels to another architecture and stays valid.
constexpr char kMagic[8] = {'P', 'L', 'C', 'L', 'B', 'I', 'N', '1'};

}  // namespace

std::filesystem::path ProgramBinaryCache::path_for(std::string_view name,
                                                   std::string_view key) const {
  return dir_ / fmt::format("{}-{:016x}.clbin", file_name_part(name), fnv1a64(key));
}

ProgramBinaryCache::Entry ProgramBinaryCache::load(std::string_view name,
                                                   std::string_view key) const {
  Entry entry;
  const ChecksummedFile file = read_checksummed_file(path_for(name, key), sizeof kMagic);
  if (file.status == ChecksummedFile::Status::Missing) return entry;
  entry.status = Lookup::Corrupt;
  if (file.status != ChecksummedFile::Status::Ok) return entry;

  std::string_view in = file.body;
  if (in.substr(0, sizeof kMagic) != std::string_view(kMagic, sizeof kMagic)) return entry;
  in.remove_prefix(sizeof kMagic);
  std::uint64_t key_len = 0, bin_len = 0;
  if (!get_raw(in, key_len) || key_len > in.size() || in.substr(0, key_len) != key) return entry;
  in.remove_prefix(key_len);
  if (!get_raw(in, bin_len) || bin_len != in.size() || bin_len == 0) return entry;
  entry.binary.assign(in.begin(), in.end());
  entry.status = Lookup::Hit;
  return entry;
}

bool ProgramBinaryCache::store(std::string_view name, std::string_view key,
                               const std::vector<unsigned char>& binary) const {
  std::string data(kMagic, sizeof kMagic);
  put_raw(data, static_cast<std::uint64_t>(key.size()));
  data.append(key);
  put_raw(data, static_cast<std::uint64_t>(binary.size()));
  data.append(reinterpret_cast<const char*>(binary.data()), binary.size());
  return write_checksummed_file(path_for(name, key), std::move(data));
}

void ProgramBinaryCache::remove(std::string_view name, std::string_view key) const {
  std::error_code ec;
  std::filesystem::remove(path_for(name, key), ec);
}

}  // namespace probeless
