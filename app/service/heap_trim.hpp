#pragma once
// Gives the C library's free heap back to the kernel now and then (issue #20 item 8, the
// soak's "RSS flat within 5 %"). glibc raises its mmap threshold to the size of the largest
// block freed (up to 32 MiB), so after the first light keyframe is dropped the keyframes'
// ~3.5 MB images and every frame buffer come from the arenas' heaps, whose free holes between
// live blocks stay resident: the 10-minute soak grew 550 -> 619 MB with the keyframe count
// already at its cap. Fixing the threshold instead (MALLOC_MMAP_THRESHOLD_=131072) held RSS
// flat but made every frame buffer a fresh mmap: 2.7x the page faults and ~5 CPU-ms more per
// frame in `bench pipeline --prerender` (docs/security.md "Memory"). malloc_trim(0) releases
// the whole free pages inside the heaps too (madvise), at a few ms every few seconds.
#include <chrono>
#include <cstddef>
#include <optional>

namespace probeless {

class HeapTrimmer {
 public:
  explicit HeapTrimmer(std::chrono::seconds every = std::chrono::seconds(10)) : every_(every) {}
  // Trims when `every` has passed since the last trim (the first call trims); returns true
  // when it trimmed.
  bool maybe_trim();
  std::size_t trims() const { return trims_; }

 private:
  std::chrono::seconds every_;
  std::optional<std::chrono::steady_clock::time_point> last_;  // none: the next call trims
  std::size_t trims_ = 0;
};

// The bytes the allocator holds free (in arenas and heaps, resident or not): mallinfo2's fordblks.
std::size_t heap_free_bytes();

}  // namespace probeless
