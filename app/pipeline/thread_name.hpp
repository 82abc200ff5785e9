#pragma once
// Names the calling thread (at most 15 characters, Linux's limit) so that `perf`, `top -H` and
// `bench pipeline`'s CPU per thread tell the pipeline's threads apart; and lowers the priority
// of a thread that is not on a frame's path.
#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <string>

namespace probeless {

inline void name_this_thread(const std::string& name) {
  pthread_setname_np(pthread_self(), name.substr(0, 15).c_str());
}

// The light thread's nice value: CFS then gives it about a tenth of a frame thread's share
// of a busy core (weights 110 against 1024), and all it wants when the cores are idle.
inline constexpr int kLightThreadNice = 10;

// Lowers the calling thread's scheduling priority to `nice` (Linux: a thread's own nice value;
// raising it needs no privilege). Best effort: a refusal leaves the thread as it was. Threads
// created afterwards inherit it, so call it after the thread's OpenCL context exists (PoCL's
// workers must keep the frames' priority).
inline void lower_this_thread_priority(int nice) {
  (void)setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), nice);
}

}  // namespace probeless
