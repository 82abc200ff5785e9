// HeapTrimmer (app/service/heap_trim.hpp): free heap memory trapped between live blocks goes
// back to the kernel, which is what kept the soak's RSS climbing (issue #20 item 8).
#include "app/service/heap_trim.hpp"

#include <gtest/gtest.h>
#include <malloc.h>

#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace probeless {
namespace {

double resident_mb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0;
}

TEST(HeapTrimmer, TrimsAtMostOncePerInterval) {
  HeapTrimmer trimmer(std::chrono::seconds(3600));
  EXPECT_TRUE(trimmer.maybe_trim()) << "the first call trims";
  EXPECT_FALSE(trimmer.maybe_trim()) << "trimmed again within the interval";
  EXPECT_EQ(trimmer.trims(), 1u);
}

// The soak's pattern: blocks of a few MB that the allocator keeps in its heap (below the mmap
// threshold, as glibc sets it after the first large free), every other one freed, so no free
// block sits at the top of the heap where the allocator's own trimming could return it.
TEST(HeapTrimmer, ReturnsFreePagesBetweenLiveBlocksToTheKernel) {
#if defined(__SANITIZE_ADDRESS__)
  // ASan replaces glibc's allocator (mallopt answers 0): there is no glibc heap to trim.
  GTEST_SKIP() << "glibc's heap only: ASan's allocator replaces it";
#endif
  // What glibc does by itself after freeing a 32 MiB mmapped block: larger blocks in the heap.
  ASSERT_EQ(mallopt(M_MMAP_THRESHOLD, 32 << 20), 1);
  constexpr std::size_t kBlock = 3 << 20;  // a 192 px keyframe cubemap is ~3.5 MB
  std::vector<std::unique_ptr<char[]>> blocks;
  for (int i = 0; i < 40; ++i) {
    blocks.emplace_back(new char[kBlock]);
    std::memset(blocks.back().get(), 1, kBlock);  // resident
  }
  for (std::size_t i = 0; i + 1 < blocks.size(); i += 2) blocks[i].reset();
  const double before = resident_mb();
  const std::size_t free_bytes = heap_free_bytes();
  EXPECT_GE(free_bytes, 19 * kBlock) << "the freed blocks are not the allocator's free heap";
  HeapTrimmer trimmer;
  ASSERT_TRUE(trimmer.maybe_trim());
  const double after = resident_mb();
  // 20 x 3 MiB freed: at least 40 MB of it must leave the resident set.
  EXPECT_LT(after, before - 40.0) << "RSS " << before << " -> " << after << " MB";
  blocks.clear();
  mallopt(M_MMAP_THRESHOLD, 128 << 10);
}

}  // namespace
}  // namespace probeless
