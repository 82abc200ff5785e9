// The disk cache of bakes (docs/prt.md "Cache"): a second bake loads, a damaged file is
// rebaked, never trusted, and never crashes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "app/render/prt/prt.hpp"
#include "app/render/prt/prt_cache.hpp"
#include "base/hash.hpp"

namespace probeless::prt {
namespace {

namespace fs = std::filesystem;

class PrtCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path("/tmp") / ("prt-cache-test-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  BakeOptions options() const {
    BakeOptions o;
    o.samples = 64;
    o.cache_dir = dir_;
    return o;
  }
  fs::path only_file() const {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir_)) files.push_back(e.path());
    EXPECT_EQ(files.size(), 1u);
    return files.empty() ? fs::path() : files.front();
  }

  const render::Mesh mesh_ = render::make_pawn(0.2f, 16);
  const Scene scene_{.ground = Ground{.subdivisions = 8}};
  fs::path dir_;
};

TEST_F(PrtCacheTest, SecondBakeIsLoaded) {
  const Bake first = bake_prt(mesh_, scene_, options());
  EXPECT_EQ(first.cache, CacheOutcome::Missing);
  EXPECT_TRUE(first.stored);
  const Bake second = bake_prt(mesh_, scene_, options());
  EXPECT_EQ(second.cache, CacheOutcome::Hit);
  EXPECT_TRUE(second.from_cache());
  EXPECT_FALSE(second.stored);
  EXPECT_EQ(second.object, first.object);
  EXPECT_EQ(second.ground_with_object, first.ground_with_object);
  EXPECT_EQ(second.ground_without_object, first.ground_without_object);
  EXPECT_EQ(second.ground.positions, first.ground.positions);
  // Without a cache directory nothing is read or written.
  BakeOptions off = options();
  off.cache_dir.clear();
  EXPECT_EQ(bake_prt(mesh_, scene_, off).cache, CacheOutcome::Off);
}

TEST_F(PrtCacheTest, EveryInputIsPartOfTheKey) {
  const Bake base = bake_prt(mesh_, scene_, options());
  auto misses = [&](const render::Mesh& m, const Scene& s, const BakeOptions& o) {
    return bake_prt(m, s, o).cache == CacheOutcome::Missing;
  };
  BakeOptions o = options();
  o.seed = 9;
  EXPECT_TRUE(misses(mesh_, scene_, o));
  o = options();
  o.samples = 32;
  EXPECT_TRUE(misses(mesh_, scene_, o));
  Scene s = scene_;
  s.mirror = true;
  EXPECT_TRUE(misses(mesh_, s, options()));
  s.mirror_reflectance = 0.5f;
  EXPECT_TRUE(misses(mesh_, s, options()));
  s = scene_;
  s.ground->plane.point.z() = -0.01f;
  EXPECT_TRUE(misses(mesh_, s, options()));
  s = scene_;
  s.ground->side = 0.5f;
  EXPECT_TRUE(misses(mesh_, s, options()));
  render::Mesh moved = mesh_;
  moved.positions[3].x() += 1e-6f;
  EXPECT_TRUE(misses(moved, scene_, options()));
  // The thread count is not: it does not change the numbers.
  o = options();
  o.threads = 1;
  EXPECT_EQ(bake_prt(mesh_, scene_, o).cache, CacheOutcome::Hit);
  (void)base;
}

TEST_F(PrtCacheTest, DamagedFilesAreRebaked) {
  const Bake first = bake_prt(mesh_, scene_, options());
  const fs::path file = only_file();
  const auto size = fs::file_size(file);
  auto rebake_matches = [&](const char* what) {
    const Bake b = bake_prt(mesh_, scene_, options());
    EXPECT_EQ(b.cache, CacheOutcome::Corrupt) << what;
    EXPECT_TRUE(b.stored) << what;
    EXPECT_EQ(b.object, first.object) << what;
    EXPECT_EQ(b.ground_with_object, first.ground_with_object) << what;
    EXPECT_EQ(bake_prt(mesh_, scene_, options()).cache, CacheOutcome::Hit) << what;
  };
  {  // one flipped bit in the payload
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    char c = 0;
    f.read(&c, 1);
    f.seekp(static_cast<std::streamoff>(size / 2));
    c = static_cast<char>(c ^ 0x10);
    f.write(&c, 1);
  }
  rebake_matches("flipped bit");
  fs::resize_file(file, size / 3);
  rebake_matches("truncated");
  fs::resize_file(file, 3);
  rebake_matches("shorter than the header");
  { std::ofstream(file, std::ios::trunc) << "not a cache file at all, but long enough to parse"; }
  rebake_matches("foreign file");
}

// A file that is whole but holds another key (a hash collision, or a file copied in) or
// other vertex counts is not used either.
TEST_F(PrtCacheTest, WholeFileForAnotherKeyIsRejected) {
  const TransferCache cache(dir_);
  Transfer t;
  t.coefficients.assign(2 * kTransferCount, 0.5f);
  ASSERT_TRUE(cache.store("m", "key one", {&t}));
  fs::rename(cache.path_for("m", "key one"), cache.path_for("m", "key two"));
  EXPECT_EQ(cache.load("m", "key two", {2}).status, TransferCache::Lookup::Corrupt);
  ASSERT_TRUE(cache.store("m", "key one", {&t}));
  EXPECT_EQ(cache.load("m", "key one", {3}).status, TransferCache::Lookup::Corrupt);
  EXPECT_EQ(cache.load("m", "key one", {2, 2}).status, TransferCache::Lookup::Corrupt);
  const auto hit = cache.load("m", "key one", {2});
  ASSERT_EQ(hit.status, TransferCache::Lookup::Hit);
  EXPECT_EQ(hit.blocks.at(0), t);
  EXPECT_EQ(cache.load("m", "key three", {2}).status, TransferCache::Lookup::Missing);
}

// Files written before the cache moved onto base/atomic_file.hpp must stay valid: the name
// and the bytes of a small entry, as that code wrote them (size and FNV-1a of the file).
TEST_F(PrtCacheTest, FileNameAndBytesArePinned) {
  const TransferCache cache(dir_);
  Transfer a, b;
  for (int i = 0; i < 2 * kTransferCount; ++i) a.coefficients.push_back(0.5f * i - 3.f);
  for (int i = 0; i < kTransferCount; ++i) b.coefficients.push_back(1.f / (i + 1));
  ASSERT_TRUE(cache.store("pawn", "prt bake key", {&a, &b}));
  const fs::path file = cache.path_for("pawn", "prt bake key");
  EXPECT_EQ(file.filename(), "prt-pawn-bc0abbc9be57a331.bin");
  std::string bytes(fs::file_size(file), '\0');
  std::ifstream(file, std::ios::binary)
      .read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  EXPECT_EQ(bytes.size(), 368u);
  EXPECT_EQ(fnv1a64(bytes), 0x77f5d414da853215ULL);
  const auto hit = cache.load("pawn", "prt bake key", {2, 1});
  ASSERT_EQ(hit.status, TransferCache::Lookup::Hit);
  EXPECT_EQ(hit.blocks.at(0), a);
  EXPECT_EQ(hit.blocks.at(1), b);
}

TEST_F(PrtCacheTest, UnwritableDirectoryStillBakes) {
  BakeOptions o = options();
  o.cache_dir = "/proc/prt-cannot-write-here";
  const Bake b = bake_prt(mesh_, scene_, o);
  EXPECT_EQ(b.cache, CacheOutcome::Missing);
  EXPECT_FALSE(b.stored);
  EXPECT_EQ(b.object.vertex_count(), mesh_.vertex_count());
}

}  // namespace
}  // namespace probeless::prt
