// The device sources' shared reopen clock and error message (drivers/device_health.hpp).
#include "drivers/device_health.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace probeless {
namespace {

using namespace std::chrono_literals;

TEST(ReopenClock, DueAtOnceUntilTheFirstLookThenAPeriodAfterEachLook) {
  ReopenClock clock(200);
  EXPECT_TRUE(clock.due());  // a new source looks at once
  clock.looked();
  EXPECT_FALSE(clock.due());
  EXPECT_GE(clock.next_ns() - monotonic_now_ns(), ms_to_ns(150));
}

TEST(ReopenClock, WaitEndsAtTheCallersDeadlineWhenTheLookIsLater) {
  ReopenClock clock(1000);
  clock.looked();
  const TimestampNs t0 = monotonic_now_ns();
  EXPECT_FALSE(clock.wait_until_due(t0 + ms_to_ns(30)));
  const TimestampNs took = monotonic_now_ns() - t0;
  EXPECT_GE(took, ms_to_ns(30));   // waited, did not spin
  EXPECT_LT(took, ms_to_ns(900));  // and not until the look
}

TEST(ReopenClock, WaitEndsAtTheLookWhenItComesFirst) {
  ReopenClock clock(30);
  clock.looked();
  const TimestampNs t0 = monotonic_now_ns();
  EXPECT_TRUE(clock.wait_until_due(t0 + ms_to_ns(5000)));
  EXPECT_LT(monotonic_now_ns() - t0, ms_to_ns(2000));
}

TEST(SharedMessage, SetOnOneThreadReadOnAnother) {
  SharedMessage message;
  EXPECT_EQ(message.get(), "");
  std::jthread writer([&] {
    for (int i = 0; i < 1000; ++i) message.set(i % 2 ? "device lost" : "no such device");
  });
  for (int i = 0; i < 1000; ++i) {
    const std::string m = message.get();
    EXPECT_TRUE(m.empty() || m == "device lost" || m == "no such device") << m;
  }
}

}  // namespace
}  // namespace probeless
