#include "common/process/exit_deadline.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <thread>

namespace mostar {
namespace {

using namespace std::chrono_literals;

// Waits up to 10 s for `flag` (a bound, not a timing expectation).
bool WaitFor(const std::atomic<bool>& flag) {
  for (int i = 0; i < 1000 && !flag.load(); ++i) std::this_thread::sleep_for(10ms);
  return flag.load();
}

TEST(ExitDeadlineTest, ExpiresWhenTheGuardedPartDoesNotFinish) {
  std::atomic<bool> expired{false};
  ExitDeadline deadline(20ms, [&expired] { expired = true; });
  EXPECT_TRUE(WaitFor(expired));
}

TEST(ExitDeadlineTest, DestroyedBeforeTheDeadlineItNeverExpires) {
  std::atomic<bool> expired{false};
  {
    ExitDeadline deadline(std::chrono::hours(1), [&expired] { expired = true; });
  }
  EXPECT_FALSE(expired.load());
}

TEST(ExitDeadlineTest, EndsAProcessThatHangsWithItsStatusAndSaysWhy) {
  EXPECT_EXIT(
      {
        ExitDeadline deadline(50ms, 4, "robot_server", "DDS teardown");
        std::this_thread::sleep_for(30s);  // the hang
        std::_Exit(0);
      },
      ::testing::ExitedWithCode(4),
      "robot_server: DDS teardown did not finish within 0.05 s: ending now \\(exit status 4\\)");
}

TEST(ExitDeadlineTest, AProcessThatEndsInTimeKeepsItsOwnStatus) {
  EXPECT_EXIT(
      {
        { ExitDeadline deadline(std::chrono::hours(1), 4, "robot_server", "DDS teardown"); }
        std::_Exit(0);
      },
      ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace mostar
