#include "app/service/signals.hpp"

#include <gtest/gtest.h>
#include <poll.h>

#include <condition_variable>
#include <csignal>
#include <mutex>
#include <thread>

namespace probeless {
namespace {

using namespace std::chrono_literals;

TEST(ShutdownSignals, SigtermWakesTheWaiter) {
  ShutdownSignals signals;
  EXPECT_FALSE(signals.stop_requested());
  EXPECT_FALSE(signals.wait_for(10ms));
  std::thread waiter([&] { EXPECT_TRUE(signals.wait_for(60s)); });
  std::this_thread::sleep_for(20ms);
  ASSERT_EQ(raise(SIGTERM), 0);
  waiter.join();
  EXPECT_TRUE(signals.stop_requested());
  EXPECT_TRUE(signals.token().stop_requested());
  EXPECT_EQ(signals.signal_number(), SIGTERM);
}

TEST(ShutdownSignals, SigintFromAnotherThreadStopsAConditionWait) {
  ShutdownSignals signals;
  std::mutex m;
  std::condition_variable_any cv;
  bool woke = false;
  std::thread worker([&] {
    std::unique_lock lock(m);
    cv.wait(lock, signals.token(), [] { return false; });  // returns when stop is requested
    woke = true;
  });
  std::thread([] { raise(SIGINT); }).join();
  worker.join();
  EXPECT_TRUE(woke);
  EXPECT_EQ(signals.signal_number(), SIGINT);
}

TEST(ShutdownSignals, TheFdBecomesReadableAndStaysSo) {
  ShutdownSignals signals;
  pollfd p{signals.fd(), POLLIN, 0};
  EXPECT_EQ(poll(&p, 1, 0), 0);
  raise(SIGTERM);
  EXPECT_EQ(poll(&p, 1, 5000), 1);
  EXPECT_EQ(poll(&p, 1, 0), 1);
}

TEST(ShutdownSignals, StopFromCodeWakesAlike) {
  ShutdownSignals signals;
  signals.request_stop();
  EXPECT_TRUE(signals.wait_for(1s));
  EXPECT_EQ(signals.signal_number(), 0);
}

TEST(ShutdownSignals, OneAtATimeAndHandlersRestored) {
  {
    ShutdownSignals signals;
    EXPECT_THROW(ShutdownSignals{}, std::logic_error);
  }
  struct sigaction current {};
  sigaction(SIGTERM, nullptr, &current);
  EXPECT_EQ(current.sa_handler, SIG_DFL);
  ShutdownSignals again;  // a new instance after the first is gone
}

TEST(ShutdownSignalsDeathTest, ASecondSignalKillsAHungShutdown) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        ShutdownSignals signals;
        raise(SIGTERM);
        signals.wait_for(5s);
        raise(SIGTERM);  // default action now
        std::this_thread::sleep_for(5s);
        std::exit(0);
      },
      ::testing::KilledBySignal(SIGTERM), "");
}

}  // namespace
}  // namespace probeless
