#include "app/pipeline/tracking_worker.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace probeless {
namespace {

TEST(TrackingWorker, RunsEachJobOnItsOwnThreadWhileTheCallerWorks) {
  TrackingWorker worker;
  std::vector<int> order;
  std::atomic<bool> caller_done{false};
  std::thread::id job_thread;
  for (int i = 0; i < 5; ++i) {
    caller_done = false;
    worker.submit([&, i] {
      job_thread = std::this_thread::get_id();
      // The caller's work overlaps the job's: the job sees it finish.
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
      while (!caller_done && std::chrono::steady_clock::now() < until) std::this_thread::yield();
      order.push_back(i);
    });
    caller_done = true;
    worker.wait();
    EXPECT_NE(job_thread, std::this_thread::get_id());
  }
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(TrackingWorker, RethrowsWhatTheJobThrewAndGoesOn) {
  TrackingWorker worker;
  worker.submit([] { throw std::runtime_error("tracker failed"); });
  EXPECT_THROW(worker.wait(), std::runtime_error);
  bool ran = false;
  worker.submit([&] { ran = true; });
  worker.wait();
  EXPECT_TRUE(ran);
}

TEST(TrackingWorker, ASecondSubmitBeforeTheWaitIsAnError) {
  TrackingWorker worker;
  std::atomic<bool> release{false};
  worker.submit([&] {
    while (!release) std::this_thread::yield();
  });
  EXPECT_THROW(worker.submit([] {}), std::logic_error);
  release = true;
  worker.wait();
}

}  // namespace
}  // namespace probeless
