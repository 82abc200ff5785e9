#include "base/latest_frame.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

namespace probeless {
namespace {

using namespace std::chrono_literals;

TEST(LatestFrame, StartsEmptyAndTimesOut) {
  LatestFrame<int> slot;
  EXPECT_EQ(slot.sequence(), 0u);
  EXPECT_FALSE(slot.try_newer(0));
  EXPECT_FALSE(slot.wait_newer(0, 10ms));
  EXPECT_FALSE(slot.peek());
}

TEST(LatestFrame, ReaderGetsOnlyNewerValues) {
  LatestFrame<int> slot;
  EXPECT_EQ(slot.publish(7), 1u);
  auto item = slot.try_newer(0);
  ASSERT_TRUE(item);
  EXPECT_EQ(item->sequence, 1u);
  EXPECT_EQ(item->value, 7);
  EXPECT_FALSE(slot.try_newer(item->sequence));
  slot.publish(8);
  item = slot.wait_newer(item->sequence, 1s);
  ASSERT_TRUE(item);
  EXPECT_EQ(item->value, 8);
  EXPECT_EQ(slot.drops(), 0u);
}

TEST(LatestFrame, ReplacingAnUnreadValueCountsADrop) {
  LatestFrame<int> slot;
  slot.publish(1);
  slot.publish(2);  // 1 was never read
  slot.publish(3);  // nor 2
  EXPECT_EQ(slot.drops(), 2u);
  EXPECT_EQ(slot.try_newer(0)->value, 3);
  slot.publish(4);  // 3 was read
  EXPECT_EQ(slot.drops(), 2u);
  // peek() does not count as reading: status pages must not hide drops.
  ASSERT_TRUE(slot.peek());
  slot.publish(5);
  EXPECT_EQ(slot.drops(), 3u);
}

TEST(LatestFrame, TakeMovesTheValueOut) {
  LatestFrame<std::unique_ptr<int>> slot;
  slot.publish(std::make_unique<int>(42));
  auto item = slot.take_newer(0, 1s);
  ASSERT_TRUE(item);
  ASSERT_TRUE(item->value);
  EXPECT_EQ(*item->value, 42);
  EXPECT_FALSE(slot.take_newer(0, 10ms));  // empty until the next publish
  slot.publish(std::make_unique<int>(43));
  EXPECT_EQ(slot.drops(), 0u);
  EXPECT_EQ(*slot.take_newer(item->sequence, 1s)->value, 43);
}

TEST(LatestFrame, CloseWakesWaitersButStillHandsOutANewerValue) {
  LatestFrame<int> slot;
  std::atomic<bool> woke{false};
  std::thread waiter([&] {
    EXPECT_FALSE(slot.wait_newer(0, 60s));
    woke = true;
  });
  std::this_thread::sleep_for(20ms);
  slot.close();
  waiter.join();
  EXPECT_TRUE(woke);
  EXPECT_TRUE(slot.closed());
  slot.publish(1);
  EXPECT_TRUE(slot.wait_newer(0, 60s));
}

TEST(LatestFrame, StopTokenWakesAWaiter) {
  LatestFrame<int> slot;
  std::stop_source stop;
  std::thread waiter([&] { EXPECT_FALSE(slot.wait_newer(0, 60s, stop.get_token())); });
  std::this_thread::sleep_for(20ms);
  stop.request_stop();
  waiter.join();
}

// A fast producer and a slower consumer: the consumer sees strictly increasing values,
// never waits behind a backlog, and every value is either read or counted as a drop.
TEST(LatestFrame, ConcurrentProducerAndConsumerAccountForEveryValue) {
  LatestFrame<std::shared_ptr<const std::vector<int>>> slot;
  constexpr int kValues = 20000;
  std::vector<int> seen;
  std::thread consumer([&] {
    LatestFrame<std::shared_ptr<const std::vector<int>>>::Sequence have = 0;
    for (;;) {
      auto item = slot.wait_newer(have, 5s);
      if (!item) break;  // closed and drained (or a 5 s stall, which fails below)
      EXPECT_GT(item->sequence, have);
      have = item->sequence;
      ASSERT_EQ(item->value->size(), 3u);
      EXPECT_EQ((*item->value)[0], (*item->value)[2]);  // never a torn value
      seen.push_back((*item->value)[0]);
      if (seen.size() % 64 == 0) std::this_thread::sleep_for(50us);
    }
  });
  for (int i = 1; i <= kValues; ++i) {
    slot.publish(std::make_shared<const std::vector<int>>(std::vector<int>{i, -i, i}));
  }
  slot.close();
  consumer.join();
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back(), kValues);  // the last value is never lost
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end());
  EXPECT_EQ(seen.size() + slot.drops(), static_cast<std::size_t>(kValues));
}

// Two readers of one slot (the HTTP thread and a file writer, say) both follow it.
TEST(LatestFrame, SeveralReadersEachSeeTheNewestValue) {
  LatestFrame<int> slot;
  constexpr int kValues = 5000;
  auto reader = [&](int& last) {
    LatestFrame<int>::Sequence have = 0;
    while (auto item = slot.wait_newer(have, 5s)) {
      EXPECT_GT(item->value, last);
      last = item->value;
      have = item->sequence;
    }
  };
  int last_a = 0, last_b = 0;
  std::thread a(reader, std::ref(last_a)), b(reader, std::ref(last_b));
  for (int i = 1; i <= kValues; ++i) slot.publish(i);
  slot.close();
  a.join();
  b.join();
  EXPECT_EQ(last_a, kValues);
  EXPECT_EQ(last_b, kValues);
}

}  // namespace
}  // namespace probeless
