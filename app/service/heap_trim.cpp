#include "app/service/heap_trim.hpp"

#include <malloc.h>
#include <spdlog/spdlog.h>

namespace probeless {

bool HeapTrimmer::maybe_trim() {
  const auto now = std::chrono::steady_clock::now();
  if (last_ && now - *last_ < every_) return false;
  last_ = now;
  // mallinfo2 walks every arena under its lock: only when someone reads the figure.
  const bool logged = spdlog::should_log(spdlog::level::debug);
  const std::size_t free_before = logged ? heap_free_bytes() : 0;
  malloc_trim(0);
  ++trims_;
  if (logged)
    spdlog::debug(
        "heap trim: {:.1f} MB free in the heap, {:.1f} ms", double(free_before) / 1e6,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - now).count());
  return true;
}

std::size_t heap_free_bytes() {
  return mallinfo2().fordblks;
}

}  // namespace probeless
