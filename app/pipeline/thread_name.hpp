#pragma once
// Names the calling thread (at most 15 characters, Linux's limit) so that `perf`, `top -H` and
// `bench pipeline`'s CPU per thread tell the pipeline's threads apart; and lowers the priority
// of a thread that is not on a frame's path.
#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <string>

namespace probeless {

inline void name_this_thread(const std::string& name) {
  pthread_setname_np(pthread_self(), name.substr(0, 15).c_str());
}

// How far the light thread's nice value goes above the process's: at +10 CFS gives it about a
// tenth of a frame thread's share of a busy core (weights 110 against 1024), and all it wants
// when the cores are idle.
inline constexpr int kLightThreadNiceSteps = 10;

// Lowers the calling thread's scheduling priority by `steps` nice levels (Linux: a thread's own
// nice value), to 19 at most; never raises it, so a service started at a high nice stays
// below it. Best effort: a refusal leaves the thread as it was. Threads created afterwards
// inherit it, so call it after the thread's OpenCL context exists (PoCL's workers must keep
// the frames' priority).
inline void lower_this_thread_priority(int steps) {
  const auto self = static_cast<id_t>(gettid());
  errno = 0;
  const int now = getpriority(PRIO_PROCESS, self);  // -1 is a valid nice value: errno tells
  if (errno != 0 || steps <= 0) return;
  (void)setpriority(PRIO_PROCESS, self, std::min(19, now + steps));
}

}  // namespace probeless
