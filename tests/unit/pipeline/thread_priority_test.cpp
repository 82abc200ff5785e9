// The light thread gives way to the frames' threads (thread_name.hpp): its nice value is its
// own, not the process's.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <thread>

#include "app/pipeline/thread_name.hpp"

namespace probeless {
namespace {

int own_nice() {
  return getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));
}

TEST(ThreadPriority, LoweringAThreadLeavesTheOthersAsTheyWere) {
  const int before = own_nice();
  if (before >= kLightThreadNice) GTEST_SKIP() << "the test runs at nice " << before;
  int lowered = before, inherited = before;
  std::thread light([&] {
    lower_this_thread_priority(kLightThreadNice);
    lowered = own_nice();
    std::thread child([&] { inherited = own_nice(); });
    child.join();
  });
  light.join();
  EXPECT_EQ(lowered, kLightThreadNice);
  EXPECT_EQ(inherited, kLightThreadNice) << "threads it starts later inherit it";
  EXPECT_EQ(own_nice(), before) << "the calling thread keeps its priority";
}

}  // namespace
}  // namespace probeless
