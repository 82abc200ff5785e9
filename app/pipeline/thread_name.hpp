#pragma once
// Names the calling thread (at most 15 characters, Linux's limit) so that `perf`, `top -H` and
// `bench pipeline`'s CPU per thread tell the pipeline's threads apart.
#include <pthread.h>

#include <string>

namespace probeless {

inline void name_this_thread(const std::string& name) {
  pthread_setname_np(pthread_self(), name.substr(0, 15).c_str());
}

}  // namespace probeless
