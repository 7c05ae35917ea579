#include "operator_client/ui/frame_schedule.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

TEST(FrameScheduleTest, HeadlessDrawsOnlyANewPairALateResultOrACaptureRender) {
  FrameSchedule schedule;
  EXPECT_FALSE(schedule.Next(std::nullopt, 0, true, false).draw);  // nothing to show
  FrameSchedule::Decision d = schedule.Next(1, 1, true, false);
  EXPECT_TRUE(d.draw);
  EXPECT_TRUE(d.new_pair);
  EXPECT_FALSE(d.new_result);
  EXPECT_FALSE(schedule.Next(1, 1, true, false).draw);  // the same state again
  d = schedule.Next(1, 2, true, false);                 // its result came late
  EXPECT_TRUE(d.draw);
  EXPECT_FALSE(d.new_pair);
  EXPECT_TRUE(d.new_result);
  EXPECT_FALSE(schedule.Next(1, 2, true, false).draw);
  d = schedule.Next(1, 2, true, true);  // a capture render of the same pair
  EXPECT_TRUE(d.draw);
  EXPECT_FALSE(d.new_pair || d.new_result);
  d = schedule.Next(2, 3, true, false);
  EXPECT_TRUE(d.new_pair);
  EXPECT_FALSE(d.new_result);
}

TEST(FrameScheduleTest, AVisibleWindowDrawsEveryFrameAndStillTellsNewPairs) {
  FrameSchedule schedule;
  EXPECT_TRUE(schedule.Next(std::nullopt, 0, false, false).draw);
  EXPECT_TRUE(schedule.Next(4, 1, false, false).new_pair);
  const FrameSchedule::Decision again = schedule.Next(4, 1, false, false);
  EXPECT_TRUE(again.draw);
  EXPECT_FALSE(again.new_pair);
  EXPECT_FALSE(again.new_result);
}

TEST(FrameScheduleTest, TheTraceStartsAfterTheWarmUpFromTheFirstPresentedPair) {
  FrameSchedule schedule;
  const SteadyTime t0 = SteadyTime(std::chrono::seconds(10));
  const Duration warmup = std::chrono::seconds(2);
  EXPECT_FALSE(schedule.CountsForTrace(t0, warmup));
  EXPECT_FALSE(schedule.CountsForTrace(t0 + std::chrono::milliseconds(1999), warmup));
  EXPECT_TRUE(schedule.CountsForTrace(t0 + warmup, warmup));
  EXPECT_TRUE(schedule.CountsForTrace(t0 + std::chrono::seconds(5), Duration(0)));
}

}  // namespace
}  // namespace mostar::ui
