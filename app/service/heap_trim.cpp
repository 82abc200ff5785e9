#include "app/service/heap_trim.hpp"

#include <malloc.h>
#include <spdlog/spdlog.h>

namespace probeless {

bool HeapTrimmer::maybe_trim() {
  const auto now = std::chrono::steady_clock::now();
  if (!first_ && now - last_ < every_) return false;
  first_ = false;
  last_ = now;
  const std::size_t free_before = heap_free_bytes();
  malloc_trim(0);
  ++trims_;
  spdlog::debug(
      "heap trim: {:.1f} MB free in the heap, {:.1f} ms", double(free_before) / 1e6,
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - now).count());
  return true;
}

std::size_t heap_free_bytes() {
  return mallinfo2().fordblks;
}

}  // namespace probeless
