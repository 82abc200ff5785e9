// The disk cache of OpenCL program binaries, without a device: entries written before it
// moved onto base/atomic_file.hpp stay valid, and anything that does not check out is
// Corrupt, never a Hit.
#include "kernels/runtime/program_binary_cache.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "base/hash.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

namespace fs = std::filesystem;

class ProgramBinaryCacheTest : public ::testing::Test {
 protected:
  static std::string read(const fs::path& p) {
    std::string bytes(fs::file_size(p), '\0');
    std::ifstream(p, std::ios::binary)
        .read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return bytes;
  }

  const fs::path dir_ = testing::scratch_dir();
};

constexpr std::string_view kName = "my kernel!";
constexpr std::string_view kKey = "device X; options -O2";

// The name and the bytes of a small entry as the code before base/ wrote them.
TEST_F(ProgramBinaryCacheTest, FileNameAndBytesArePinned) {
  const ProgramBinaryCache cache(dir_);
  const std::vector<unsigned char> binary = {1, 2, 3, 250};
  ASSERT_TRUE(cache.store(kName, kKey, binary));
  const fs::path file = cache.path_for(kName, kKey);
  EXPECT_EQ(file.filename(), "my_kernel_-c916549816f9e45c.clbin");
  const std::string bytes = read(file);
  EXPECT_EQ(bytes.size(), 57u);
  EXPECT_EQ(fnv1a64(bytes), 0x6bd0a035a538679cULL);
  const auto hit = cache.load(kName, kKey);
  ASSERT_EQ(hit.status, ProgramBinaryCache::Lookup::Hit);
  EXPECT_EQ(hit.binary, binary);
}

TEST_F(ProgramBinaryCacheTest, DamagedOrForeignFilesAreCorrupt) {
  const ProgramBinaryCache cache(dir_);
  EXPECT_EQ(cache.load(kName, kKey).status, ProgramBinaryCache::Lookup::Missing);
  ASSERT_TRUE(cache.store(kName, kKey, {1, 2, 3, 250}));
  const fs::path file = cache.path_for(kName, kKey);
  const std::string good = read(file);
  auto load_of = [&](const std::string& bytes) {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    return cache.load(kName, kKey).status;
  };
  std::string flipped = good;
  flipped[20] ^= 0x10;
  EXPECT_EQ(load_of(flipped), ProgramBinaryCache::Lookup::Corrupt);
  EXPECT_EQ(load_of(good.substr(0, good.size() / 2)), ProgramBinaryCache::Lookup::Corrupt);
  EXPECT_EQ(load_of("short"), ProgramBinaryCache::Lookup::Corrupt);
  EXPECT_EQ(load_of(good), ProgramBinaryCache::Lookup::Hit);
  // Whole, but for another key.
  fs::rename(file, cache.path_for(kName, "another key"));
  EXPECT_EQ(cache.load(kName, "another key").status, ProgramBinaryCache::Lookup::Corrupt);
  cache.remove(kName, "another key");
  EXPECT_EQ(cache.load(kName, "another key").status, ProgramBinaryCache::Lookup::Missing);
}

}  // namespace
}  // namespace probeless
