#include "operator_client/video/arrival_report.h"

#include <gtest/gtest.h>

namespace mostar::client {
namespace {

SteadyTime At(int ms) { return SteadyTime(std::chrono::milliseconds(ms)); }

TEST(ArrivalReportTest, TheFirstArrivalIsReportedAtOnceThenOneReportPerPeriod) {
  ArrivalReport report;
  report.Add(1, At(1000), 5000);
  const std::vector<VideoFrameArrival> first = report.TakeDue(At(1000));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].sequence, 1u);
  EXPECT_EQ(first[0].arrival_ns, At(1000).time_since_epoch().count());
  EXPECT_EQ(first[0].bytes, 5000u);
  report.Add(2, At(1033), 4000);
  report.Add(3, At(1049), 4100);
  EXPECT_TRUE(report.TakeDue(At(1049)).empty());  // 49 ms after the last report
  const std::vector<VideoFrameArrival> second = report.TakeDue(At(1050));
  ASSERT_EQ(second.size(), 2u);
  EXPECT_EQ(second[0].sequence, 2u);
  EXPECT_EQ(second[1].sequence, 3u);
  EXPECT_EQ(report.pending(), 0u);
  EXPECT_TRUE(report.TakeDue(At(2000)).empty());  // nothing arrived
}

TEST(ArrivalReportTest, OldOrRepeatedFramesAreNotRecorded) {
  ArrivalReport report;
  report.Add(10, At(0), 1);
  report.Add(10, At(1), 1);
  report.Add(9, At(2), 1);
  report.Add(12, At(3), 1);
  EXPECT_EQ(report.not_recorded(), 2u);
  const std::vector<VideoFrameArrival> due = report.TakeDue(At(3));
  ASSERT_EQ(due.size(), 2u);
  EXPECT_EQ(due[1].sequence, 12u);
}

TEST(ArrivalReportTest, AFullReportIsDueBeforeThePeriodAndThePendingListIsBounded) {
  ArrivalReport report;
  report.Add(1, At(0), 1);
  ASSERT_EQ(report.TakeDue(At(0)).size(), 1u);
  const size_t max = VideoFeedback::kMaxArrivals;
  for (uint64_t s = 2; s < 2 + 5 * max; ++s) report.Add(s, At(1), 1);
  EXPECT_EQ(report.pending(), 4 * max);
  EXPECT_EQ(report.not_recorded(), max);
  const std::vector<VideoFrameArrival> due = report.TakeDue(At(2));  // within the period
  EXPECT_EQ(due.size(), max);
  EXPECT_EQ(due.front().sequence, 2u);
  EXPECT_EQ(report.pending(), 3 * max);
}

}  // namespace
}  // namespace mostar::client
