#pragma once
// Baked transfer on disk, so a restart with the same model and settings loads in milliseconds
// instead of baking again (docs/prt.md "Cache"). The pattern of the OpenCL program cache
// (kernels/runtime/program_binary_cache.hpp): one file per key, the full key repeated inside,
// a checksum over everything, atomic writes (both through base/atomic_file.hpp); anything
// that does not check out is Corrupt and the caller rebakes.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "app/render/prt/prt.hpp"

namespace probeless::prt {

// Everything the bake's numbers depend on, as text: the bake version, a hash of the mesh's
// positions, normals and indices, the scene (mirror, reflectance, ground) and the sampling
// (samples, seed, bounces). Not the thread count, which does not change the result.
std::string bake_cache_key(const render::Mesh& object, const Scene& scene,
                           const BakeOptions& options);

class TransferCache {
 public:
  enum class Lookup { Hit, Missing, Corrupt };
  struct Entry {
    Lookup status = Lookup::Missing;
    std::vector<Transfer> blocks;
    std::string problem;  // why a file is Corrupt, for the log
  };

  explicit TransferCache(std::filesystem::path dir) : dir_(std::move(dir)) {}

  // `name` only makes the file name readable (the mesh's name); the key decides.
  std::filesystem::path path_for(std::string_view name, std::string_view key) const;
  // Hit only when the file is whole, for this key, and holds exactly one block per entry of
  // `vertex_counts` with that many vertices.
  Entry load(std::string_view name, std::string_view key,
             const std::vector<std::size_t>& vertex_counts) const;
  // Written to a temporary file beside it, then renamed over; false (nothing left behind)
  // when the directory cannot be written.
  bool store(std::string_view name, std::string_view key,
             const std::vector<const Transfer*>& blocks) const;
  void remove(std::string_view name, std::string_view key) const;

 private:
  std::filesystem::path dir_;
};

}  // namespace probeless::prt
