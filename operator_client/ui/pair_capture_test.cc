#include "operator_client/ui/pair_capture.h"

#include <gtest/gtest.h>

#include "common/time/fake_clock.h"

namespace mostar::ui {
namespace {

using std::chrono::milliseconds;

client::DecodedStereoPair Pair(uint64_t sequence) {
  client::DecodedStereoPair pair;
  pair.sequence = sequence;
  pair.stamp =
      FromUnixNanos(1'700'000'000'000'000'000 + static_cast<int64_t>(sequence) * 40'000'000);
  return pair;
}

TEST(PairCaptureTest, LatchesThePairWithTheStampAndIgnoresLaterOnes) {
  FakeClock clock;
  PairCapture capture(Pair(7).stamp, 0);
  EXPECT_FALSE(capture.Filter(Pair(6), std::nullopt, clock.SteadyNow()));
  EXPECT_FALSE(capture.latched_stamp());
  const Time scan_after = Pair(7).stamp + milliseconds(5);
  EXPECT_FALSE(capture.Filter(Pair(6), scan_after, clock.SteadyNow()));
  auto shown = capture.Filter(Pair(7), scan_after, clock.SteadyNow());
  ASSERT_TRUE(shown);
  EXPECT_EQ(shown->sequence, 7u);
  shown = capture.Filter(Pair(8), scan_after, clock.SteadyNow());
  ASSERT_TRUE(shown);
  EXPECT_EQ(shown->sequence, 7u);
  EXPECT_EQ(capture.latched_stamp(), Pair(7).stamp);
}

TEST(PairCaptureTest, WithoutStampLatchesTheFirstPairAfterTheStart) {
  FakeClock clock;
  PairCapture capture(std::nullopt, 5);
  const Time scan = Pair(100).stamp;
  EXPECT_FALSE(capture.Filter(Pair(5), scan, clock.SteadyNow()));
  const auto shown = capture.Filter(Pair(6), scan, clock.SteadyNow());
  ASSERT_TRUE(shown);
  EXPECT_EQ(shown->sequence, 6u);
}

TEST(PairCaptureTest, WaitsForAScanStampedAtOrAfterThePair) {
  FakeClock clock;
  PairCapture capture(std::nullopt, 0);
  const Time pair_stamp = Pair(1).stamp;
  EXPECT_FALSE(capture.Filter(Pair(1), pair_stamp - milliseconds(1), clock.SteadyNow()));
  EXPECT_EQ(capture.latched_stamp(), pair_stamp);  // latched, not shown yet
  clock.Advance(milliseconds(100));
  EXPECT_FALSE(capture.Filter(Pair(2), std::nullopt, clock.SteadyNow()));
  clock.Advance(milliseconds(100));
  const auto shown = capture.Filter(Pair(3), pair_stamp, clock.SteadyNow());
  ASSERT_TRUE(shown);
  EXPECT_EQ(shown->sequence, 1u);
}

TEST(PairCaptureTest, GivesUpWaitingForTheScanAfterTwoSeconds) {
  FakeClock clock;
  PairCapture capture(std::nullopt, 0);
  EXPECT_FALSE(capture.Filter(Pair(1), std::nullopt, clock.SteadyNow()));
  clock.Advance(PairCapture::kScanWait);
  EXPECT_FALSE(capture.Filter(Pair(1), std::nullopt, clock.SteadyNow()));
  clock.Advance(milliseconds(1));
  EXPECT_TRUE(capture.Filter(Pair(1), std::nullopt, clock.SteadyNow()));
}

TEST(PairCaptureTest, IsDoneAfterThreeRendersWithTheEdgeResult) {
  FakeClock clock;
  PairCapture capture(std::nullopt, 0);
  const auto shown = capture.Filter(Pair(4), Pair(4).stamp, clock.SteadyNow());
  ASSERT_TRUE(shown);
  // With edge processing, renders count only once the pair's result is in.
  EXPECT_FALSE(capture.IsCaptureRender(shown, /*vision_enabled=*/true, 3));
  EXPECT_TRUE(capture.IsCaptureRender(shown, true, 4));
  EXPECT_TRUE(capture.IsCaptureRender(shown, /*vision_enabled=*/false, 3));
  // Another pair on screen (the picker still shows an older one) does not count.
  EXPECT_FALSE(capture.IsCaptureRender(Pair(3), false, 3));
  EXPECT_FALSE(capture.IsCaptureRender(std::nullopt, false, 3));
  for (int i = 1; i < PairCapture::kRenders; ++i) {
    EXPECT_FALSE(capture.CountRender()) << i;
    EXPECT_FALSE(capture.done());
  }
  EXPECT_TRUE(capture.CountRender());
  EXPECT_TRUE(capture.done());
  EXPECT_FALSE(capture.IsCaptureRender(shown, false, 4));
  EXPECT_FALSE(capture.CountRender());
}

TEST(PairCaptureTest, WaitsForTheOdometryThatMovesTheScanToThePair) {
  FakeClock clock;
  PairCapture capture(std::nullopt, 0);
  const Time pair_stamp = Pair(1).stamp;
  const Time scan_after = pair_stamp + milliseconds(20);
  // The scan is in, but the odometry has not reached past the pair by kOdometryAfter yet.
  EXPECT_FALSE(capture.Filter(Pair(1), scan_after, clock.SteadyNow(),
                              pair_stamp + PairCapture::kOdometryAfter - milliseconds(1)));
  clock.Advance(milliseconds(30));
  const auto shown = capture.Filter(Pair(2), scan_after, clock.SteadyNow(),
                                    pair_stamp + PairCapture::kOdometryAfter);
  ASSERT_TRUE(shown);
  EXPECT_EQ(shown->sequence, 1u);
}

TEST(PairCaptureTest, GivesUpWaitingForTheOdometryAfterTwoSeconds) {
  FakeClock clock;
  PairCapture capture(std::nullopt, 0);
  const Time pair_stamp = Pair(1).stamp;
  EXPECT_FALSE(capture.Filter(Pair(1), pair_stamp, clock.SteadyNow(), pair_stamp));
  clock.Advance(PairCapture::kScanWait + milliseconds(1));
  EXPECT_TRUE(capture.Filter(Pair(1), pair_stamp, clock.SteadyNow(), pair_stamp));
}

TEST(PairCaptureTest, StampOfAnOptionalMessage) {
  EXPECT_FALSE(StampOf(std::optional<client::DecodedStereoPair>()));
  EXPECT_EQ(StampOf(std::optional<client::DecodedStereoPair>(Pair(3))), Pair(3).stamp);
}

TEST(PairCaptureTest, NotACaptureRenderBeforeTheScansAreIn) {
  FakeClock clock;
  PairCapture capture(std::nullopt, 0);
  EXPECT_FALSE(capture.Filter(Pair(1), std::nullopt, clock.SteadyNow()));
  EXPECT_FALSE(capture.IsCaptureRender(Pair(1), false, 0));
}

}  // namespace
}  // namespace mostar::ui
