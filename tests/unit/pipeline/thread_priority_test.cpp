// The light thread gives way to the frames' threads (thread_name.hpp): its nice value is its
// own, not the process's.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <thread>

#include "app/pipeline/thread_name.hpp"

namespace probeless {
namespace {

int own_nice() {
  return getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));
}

TEST(ThreadPriority, LoweringAThreadLeavesTheOthersAsTheyWere) {
  const int before = own_nice();
  if (before >= 19) GTEST_SKIP() << "the test runs at nice 19: nothing lower to go to";
  int lowered = before, inherited = before;
  std::thread light([&] {
    lower_this_thread_priority(kLightThreadNiceSteps);
    lowered = own_nice();
    std::thread child([&] { inherited = own_nice(); });
    child.join();
  });
  light.join();
  EXPECT_EQ(lowered, std::min(19, before + kLightThreadNiceSteps));
  EXPECT_EQ(inherited, lowered) << "threads it starts later inherit it";
  EXPECT_EQ(own_nice(), before) << "the calling thread keeps its priority";
}

TEST(ThreadPriority, NeverRaisesIt) {
  const int before = own_nice();
  int after = before;
  std::thread t([&] {
    lower_this_thread_priority(0);
    lower_this_thread_priority(-5);
    after = own_nice();
  });
  t.join();
  EXPECT_EQ(after, before);
}

}  // namespace
}  // namespace probeless
