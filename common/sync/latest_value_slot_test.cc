#include "common/sync/latest_value_slot.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace mostar {
namespace {

TEST(LatestValueSlotTest, TakeReturnsTheLatestValueAndCountsReplacedOnesAsDrops) {
  LatestValueSlot<int> slot;
  EXPECT_TRUE(slot.Put(1));
  EXPECT_FALSE(slot.Put(2));  // 1 was not taken
  EXPECT_FALSE(slot.Put(3));
  const std::optional<int> value = slot.TryTake();
  ASSERT_TRUE(value.has_value());
  EXPECT_EQ(*value, 3);
  EXPECT_FALSE(slot.TryTake().has_value());
  const auto counters = slot.counters();
  EXPECT_EQ(counters.puts, 3u);
  EXPECT_EQ(counters.drops, 2u);
  EXPECT_EQ(counters.takes, 1u);
}

TEST(LatestValueSlotTest, TakeTimesOutWhenEmpty) {
  LatestValueSlot<int> slot;
  EXPECT_FALSE(slot.Take(std::chrono::milliseconds(1)).has_value());
  EXPECT_EQ(slot.counters().takes, 0u);
}

TEST(LatestValueSlotTest, TakeWakesUpOnPutFromAnotherThread) {
  LatestValueSlot<int> slot;
  std::thread producer([&] { slot.Put(42); });
  const std::optional<int> value = slot.Take(std::chrono::seconds(10));
  producer.join();
  ASSERT_TRUE(value.has_value());
  EXPECT_EQ(*value, 42);
}

TEST(LatestValueSlotTest, CloseWakesWaitersAndIgnoresLaterPuts) {
  LatestValueSlot<int> slot;
  std::optional<int> value = 7;
  std::thread consumer([&] { value = slot.Take(std::chrono::seconds(30)); });
  slot.Close();
  consumer.join();
  EXPECT_FALSE(value.has_value());
  EXPECT_TRUE(slot.closed());
  EXPECT_FALSE(slot.Put(1));
  EXPECT_FALSE(slot.TryTake().has_value());
  EXPECT_EQ(slot.counters().puts, 0u);
}

TEST(LatestValueSlotTest, MoveOnlyValuesAreHandedOver) {
  LatestValueSlot<std::unique_ptr<int>> slot;
  slot.Put(std::make_unique<int>(5));
  auto value = slot.TryTake();
  ASSERT_TRUE(value.has_value());
  EXPECT_EQ(**value, 5);
}

// Producer, consumer and a health reader at once (the thread-sanitizer build checks the locking):
// every value offered is taken, dropped, or still pending at the end.
TEST(LatestValueSlotTest, CountersAddUpWithProducerConsumerAndReaderRunningTogether) {
  LatestValueSlot<int> slot;
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (int i = 0; i < 20000; ++i) slot.Put(i);
    done = true;
  });
  std::thread consumer([&] {
    while (!done) slot.Take(std::chrono::milliseconds(1));
  });
  uint64_t last_puts = 0;
  while (!done) {
    const auto c = slot.counters();
    EXPECT_GE(c.puts, last_puts);
    EXPECT_LE(c.takes + c.drops, c.puts);
    last_puts = c.puts;
  }
  producer.join();
  consumer.join();
  const bool pending = slot.TryTake().has_value();
  const auto c = slot.counters();
  EXPECT_EQ(c.puts, 20000u);
  EXPECT_EQ(c.takes + c.drops, c.puts) << "pending at the end: " << pending;
}

}  // namespace
}  // namespace mostar
