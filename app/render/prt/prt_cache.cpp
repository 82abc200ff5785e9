#include "app/render/prt/prt_cache.hpp"

#include <fmt/format.h>

#include <cstring>
#include <system_error>

#include "base/atomic_file.hpp"
#include "base/hash.hpp"
#include "base/raw_bytes.hpp"

namespace probeless::prt {
namespace {

// File layout, host byte order (a cache never leaves its machine):
//   magic[8] "PLPRTXF1", u32 format version, u32 coefficients per vertex (25),
//   u64 key length, key, u64 block count, u64 vertex count per block,
//   the blocks' floats one after the other, u64 FNV-1a of everything before it
//   (base/atomic_file.hpp).
constexpr char kMagic[8] = {'P', 'L', 'P', 'R', 'T', 'X', 'F', '1'};
constexpr std::uint32_t kFormatVersion = 1;

std::string safe_name(std::string_view name) {
  std::string s = file_name_part(name);
  return s.empty() ? "mesh" : s;
}

template <typename T>
std::uint64_t hash_bytes(const std::vector<T>& v, std::uint64_t seed) {
  return fnv1a64(std::string_view(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)),
                 seed);
}

}  // namespace

std::string bake_cache_key(const render::Mesh& object, const Scene& scene,
                           const BakeOptions& options) {
  // Chained FNV-1a over the raw floats and indices: any change to the geometry is a new key.
  std::uint64_t h = hash_bytes(object.positions, 0xcbf29ce484222325ULL);
  h = hash_bytes(object.normals, h);
  h = hash_bytes(object.indices, h);
  h = hash_bytes(scene.triangle_reflectance, h);
  std::string ground = "none";
  if (scene.ground) {
    const Ground& g = *scene.ground;
    ground = fmt::format("point {:a} {:a} {:a} normal {:a} {:a} {:a} side {:a} {:a} sub {}",
                         g.plane.point.x(), g.plane.point.y(), g.plane.point.z(),
                         g.plane.normal.x(), g.plane.normal.y(), g.plane.normal.z(), g.side_radii,
                         g.side.value_or(0.f), g.subdivisions);
  }
  // Hex floats: exact, so two settings that differ in the last bit are two keys.
  return fmt::format(
      "prt bake v{} sh{} mesh {:016x} vertices {} triangles {} samples {} seed {} bounces {} "
      "mirror {} {:a} ground {}",
      kBakeVersion, kTransferCount, h, object.vertex_count(), object.triangle_count(),
      options.samples, options.seed, options.max_mirror_bounces, scene.mirror ? 1 : 0,
      scene.mirror_reflectance, ground);
}

std::filesystem::path TransferCache::path_for(std::string_view name, std::string_view key) const {
  return dir_ / fmt::format("prt-{}-{:016x}.bin", safe_name(name), fnv1a64(key));
}

TransferCache::Entry TransferCache::load(std::string_view name, std::string_view key,
                                         const std::vector<std::size_t>& vertex_counts) const {
  Entry entry;
  const ChecksummedFile file = read_checksummed_file(path_for(name, key), sizeof kMagic);
  auto corrupt = [&](std::string why) {
    entry.status = Lookup::Corrupt;
    entry.problem = std::move(why);
    return entry;
  };
  switch (file.status) {
    case ChecksummedFile::Status::Ok:
      break;
    case ChecksummedFile::Status::Missing:
      return entry;
    case ChecksummedFile::Status::Unreadable:
      return corrupt("unreadable");
    case ChecksummedFile::Status::Truncated:
      return corrupt("truncated");
    case ChecksummedFile::Status::BadChecksum:
      return corrupt("checksum mismatch (truncated or damaged)");
  }

  std::string_view in = file.body;
  if (in.substr(0, sizeof kMagic) != std::string_view(kMagic, sizeof kMagic))
    return corrupt("not a PRT cache file");
  in.remove_prefix(sizeof kMagic);
  std::uint32_t version = 0, per_vertex = 0;
  if (!get_raw(in, version) || version != kFormatVersion) return corrupt("another format version");
  if (!get_raw(in, per_vertex) || per_vertex != kTransferCount)
    return corrupt("another coefficient count");
  std::uint64_t key_len = 0, blocks = 0;
  if (!get_raw(in, key_len) || key_len > in.size() || in.substr(0, key_len) != key)
    return corrupt("another key (hash collision or stale file)");
  in.remove_prefix(key_len);
  if (!get_raw(in, blocks) || blocks != vertex_counts.size()) return corrupt("wrong block count");
  std::uint64_t floats = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    std::uint64_t n = 0;
    if (!get_raw(in, n) || n != vertex_counts[b]) return corrupt("wrong vertex count");
    floats += n * kTransferCount;
  }
  if (in.size() != floats * sizeof(float)) return corrupt("wrong payload size");
  entry.blocks.resize(blocks);
  for (std::size_t b = 0; b < blocks; ++b) {
    auto& c = entry.blocks[b].coefficients;
    c.resize(vertex_counts[b] * kTransferCount);
    std::memcpy(c.data(), in.data(), c.size() * sizeof(float));
    in.remove_prefix(c.size() * sizeof(float));
  }
  entry.status = Lookup::Hit;
  return entry;
}

bool TransferCache::store(std::string_view name, std::string_view key,
                          const std::vector<const Transfer*>& blocks) const {
  std::string data(kMagic, sizeof kMagic);
  put_raw(data, kFormatVersion);
  put_raw(data, static_cast<std::uint32_t>(kTransferCount));
  put_raw(data, static_cast<std::uint64_t>(key.size()));
  data.append(key);
  put_raw(data, static_cast<std::uint64_t>(blocks.size()));
  for (const Transfer* t : blocks) put_raw(data, static_cast<std::uint64_t>(t->vertex_count()));
  for (const Transfer* t : blocks)
    data.append(reinterpret_cast<const char*>(t->coefficients.data()),
                t->coefficients.size() * sizeof(float));
  return write_checksummed_file(path_for(name, key), std::move(data));
}

void TransferCache::remove(std::string_view name, std::string_view key) const {
  std::error_code ec;
  std::filesystem::remove(path_for(name, key), ec);
}

}  // namespace probeless::prt
