#include "common/sync/wake_signal.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "common/sync/helper_thread.h"

namespace mostar {
namespace {

TEST(WakeSignalTest, WaitTimesOutWithoutANotification) {
  WakeSignal signal;
  EXPECT_FALSE(signal.WaitFor(std::chrono::milliseconds(1)));
  EXPECT_EQ(signal.notifications(), 0u);
}

TEST(WakeSignalTest, ANotificationBeforeTheWaitIsNotLostAndSeveralCountAsOne) {
  WakeSignal signal;
  signal.Notify();
  signal.Notify();
  EXPECT_TRUE(signal.WaitFor(std::chrono::seconds(5)));
  EXPECT_FALSE(signal.TakePending());
  EXPECT_FALSE(signal.WaitFor(std::chrono::milliseconds(1)));
  EXPECT_EQ(signal.notifications(), 2u);
}

TEST(WakeSignalTest, ANotificationFromAnotherThreadEndsTheWaitAndRunsTheHook) {
  WakeSignal signal;
  std::atomic<int> hooks{0};
  signal.SetHook([&hooks] { ++hooks; });
  std::thread producer([&signal] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    signal.Notify();
  });
  // A bound far beyond the producer's delay: the wait ends by the notification.
  EXPECT_TRUE(signal.WaitFor(std::chrono::seconds(30)));
  producer.join();
  EXPECT_EQ(hooks.load(), 1);
}

TEST(HelperThreadTest, RunsEachJobOnAnotherThreadAndWaitReturnsWhenItFinished) {
  HelperThread helper;
  for (int round = 0; round < 50; ++round) {
    std::atomic<bool> done{false};
    std::thread::id ran_on;
    helper.Run([&] {
      std::this_thread::sleep_for(std::chrono::microseconds(100));
      ran_on = std::this_thread::get_id();
      done = true;
    });
    helper.Wait();
    EXPECT_TRUE(done.load());
    EXPECT_NE(ran_on, std::this_thread::get_id());
  }
  helper.Wait();  // nothing running: returns at once
}

TEST(HelperThreadTest, TheDestructorWaitsForARunningJob) {
  std::atomic<bool> done{false};
  {
    HelperThread helper;
    helper.Run([&done] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      done = true;
    });
  }
  EXPECT_TRUE(done.load());
}

}  // namespace
}  // namespace mostar
