#include "operator_client/ui/run_end.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

TEST(RunEndTest, NoLimitRunsUntilAnEvent) {
  EXPECT_EQ(CheckRunEnd({}, false, 1000000, FromSeconds(3600)), RunEnd::kRunning);
}

TEST(RunEndTest, FramesAndDurationEndTheRunWhenReached) {
  const RunLimits frames{10, {}};
  EXPECT_EQ(CheckRunEnd(frames, false, 9, FromSeconds(100)), RunEnd::kRunning);
  EXPECT_EQ(CheckRunEnd(frames, false, 10, FromSeconds(0)), RunEnd::kFrames);
  const RunLimits duration{0, FromSeconds(30)};
  EXPECT_EQ(CheckRunEnd(duration, false, 5000, FromSeconds(30)), RunEnd::kRunning);
  EXPECT_EQ(CheckRunEnd(duration, false, 0, FromSeconds(30.001)), RunEnd::kDuration);
}

TEST(RunEndTest, ACapturedPairEndsTheRunBeforeAnyLimit) {
  EXPECT_EQ(CheckRunEnd({1, FromSeconds(1)}, true, 5, FromSeconds(9)), RunEnd::kCaptured);
}

TEST(RunEndTest, CaptureAfterIsDueOnceWhenEnoughPairsAreDecoded) {
  EXPECT_FALSE(CaptureAfterDue(-1, false, 100));  // not asked
  EXPECT_FALSE(CaptureAfterDue(5, false, 4));
  EXPECT_TRUE(CaptureAfterDue(5, false, 5));
  EXPECT_FALSE(CaptureAfterDue(5, true, 50));  // already armed
  EXPECT_TRUE(CaptureAfterDue(0, false, 0));
}

TEST(RunEndTest, AScreenshotIsWrittenWhenAskedForAndThereIsAFrame) {
  EXPECT_TRUE(PlanScreenshot("out.png", false, false, false, true).write);
  const ScreenshotPlan none = PlanScreenshot("", false, false, false, true);
  EXPECT_FALSE(none.write);
  EXPECT_TRUE(none.problem.empty());
  const ScreenshotPlan empty = PlanScreenshot("out.png", false, false, false, false);
  EXPECT_FALSE(empty.write);
  EXPECT_EQ(empty.problem, "no video frame was rendered; no screenshot written");
  EXPECT_EQ(empty.exit_status, 0);
}

// A capture that did not happen fails the run, says why, and writes no other frame instead.
TEST(RunEndTest, AMissedCaptureFailsAndSaysWhichPartDidNotArrive) {
  const ScreenshotPlan never = PlanScreenshot("out.png", true, false, false, true);
  EXPECT_FALSE(never.write);
  EXPECT_EQ(never.exit_status, 1);
  EXPECT_NE(never.problem.find("(it did not arrive)"), std::string::npos) << never.problem;
  const ScreenshotPlan half = PlanScreenshot("", true, false, true, true);
  EXPECT_EQ(half.exit_status, 1);
  EXPECT_NE(half.problem.find("scans or edge result"), std::string::npos) << half.problem;
  const ScreenshotPlan done = PlanScreenshot("out.png", true, true, true, true);
  EXPECT_TRUE(done.write);
  EXPECT_EQ(done.exit_status, 0);
}

}  // namespace
}  // namespace mostar::ui
