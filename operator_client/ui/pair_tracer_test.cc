#include "operator_client/ui/pair_tracer.h"

#include <gtest/gtest.h>

#include "operator_client/ui/shown_pair_stats.h"

namespace mostar::ui {
namespace {

using std::chrono::milliseconds;

const Time kWallNow = FromUnixNanos(1'800'000'000'000'000'000);
const SteadyTime kSteadyNow = SteadyTime(std::chrono::seconds(5000));

Time At(const PairTimeline& timeline, LatencyStage stage) {
  const std::optional<Time>& t = timeline.at[static_cast<int>(stage)];
  EXPECT_TRUE(t.has_value()) << LatencyStageName(stage);
  return t.value_or(Time{});
}

TEST(RobotTimeMapperTest, MapsThroughTheWallClockThenTheOffsetWhenKnown) {
  timesync::ClockOffsetEstimate offset;
  const RobotTimeMapper local(kWallNow, kSteadyNow, offset);
  EXPECT_EQ(local(kSteadyNow - milliseconds(30)), kWallNow - milliseconds(30));
  offset.known = true;
  offset.responder_minus_requester = milliseconds(250);  // the robot's clock is ahead
  const RobotTimeMapper robot(kWallNow, kSteadyNow, offset);
  EXPECT_EQ(robot(kSteadyNow - milliseconds(30)), kWallNow + milliseconds(220));
}

TEST(PairTracerTest, StampsEveryStageOnTheRobotClock) {
  timesync::ClockOffsetEstimate offset;
  offset.known = true;
  offset.responder_minus_requester = milliseconds(100);
  const RobotTimeMapper to_robot(kWallNow, kSteadyNow, offset);
  PairTracer tracer;
  tracer.Picked(7, kSteadyNow - milliseconds(20));
  ShownPairStamps pair{7, kWallNow + milliseconds(50), kSteadyNow - milliseconds(30),
                       kSteadyNow - milliseconds(28), kSteadyNow - milliseconds(25)};
  const FrameTiming robot_side{pair.capture, pair.capture + milliseconds(3),
                               pair.capture + milliseconds(4)};
  const ShowingFrame frame{kSteadyNow - milliseconds(17), kSteadyNow - milliseconds(15),
                           kSteadyNow - milliseconds(5), kSteadyNow};
  const PairTimeline t = tracer.Timeline(pair, robot_side, frame, true, to_robot);
  EXPECT_EQ(t.capture, pair.capture);
  EXPECT_EQ(At(t, LatencyStage::kEncoded), pair.capture + milliseconds(3));
  EXPECT_EQ(At(t, LatencyStage::kWritten), pair.capture + milliseconds(4));
  EXPECT_EQ(At(t, LatencyStage::kReceived), kWallNow + milliseconds(70));
  EXPECT_EQ(At(t, LatencyStage::kQueued), kWallNow + milliseconds(72));
  EXPECT_EQ(At(t, LatencyStage::kDecoded), kWallNow + milliseconds(75));
  EXPECT_EQ(At(t, LatencyStage::kPicked), kWallNow + milliseconds(80));
  EXPECT_EQ(At(t, LatencyStage::kVision), kWallNow + milliseconds(83));  // the result was ready
  EXPECT_EQ(At(t, LatencyStage::kStarted), kWallNow + milliseconds(85));
  EXPECT_EQ(At(t, LatencyStage::kDrawn), kWallNow + milliseconds(95));
  EXPECT_EQ(At(t, LatencyStage::kPresented), kWallNow + milliseconds(100));
}

TEST(PairTracerTest, WithoutEdgeProcessingVisionTakesNoTime) {
  const RobotTimeMapper to_robot(kWallNow, kSteadyNow, {});
  PairTracer tracer;
  tracer.Picked(3, kSteadyNow - milliseconds(20));
  const ShownPairStamps pair{3, kWallNow - milliseconds(60), kSteadyNow - milliseconds(30),
                             kSteadyNow - milliseconds(28), kSteadyNow - milliseconds(25)};
  const ShowingFrame frame{kSteadyNow - milliseconds(15), kSteadyNow - milliseconds(15),
                           kSteadyNow - milliseconds(5), kSteadyNow};
  const PairTimeline t = tracer.Timeline(pair, std::nullopt, frame, false, to_robot);
  EXPECT_EQ(At(t, LatencyStage::kVision), At(t, LatencyStage::kPicked));
  // The robot's stages are unknown: left unset, reported as unexplained by the trace.
  EXPECT_FALSE(t.at[static_cast<int>(LatencyStage::kEncoded)].has_value());
  EXPECT_FALSE(t.at[static_cast<int>(LatencyStage::kWritten)].has_value());
}

TEST(PairTracerTest, VisionNeverEndsBeforeThePick) {
  const RobotTimeMapper to_robot(kWallNow, kSteadyNow, {});
  PairTracer tracer;
  tracer.Picked(4, kSteadyNow - milliseconds(20));
  const ShownPairStamps pair{4, kWallNow - milliseconds(60), kSteadyNow - milliseconds(30),
                             kSteadyNow - milliseconds(28), kSteadyNow - milliseconds(25)};
  // Ready before the loop took it (a result published for a pair the loop had not seen).
  const ShowingFrame frame{kSteadyNow - milliseconds(24), kSteadyNow - milliseconds(15),
                           kSteadyNow - milliseconds(5), kSteadyNow};
  const PairTimeline t = tracer.Timeline(pair, std::nullopt, frame, true, to_robot);
  EXPECT_EQ(At(t, LatencyStage::kVision), At(t, LatencyStage::kPicked));
}

TEST(PairTracerTest, OnlyTheFirstPickCountsAndOldPairsAreForgotten) {
  const RobotTimeMapper to_robot(kWallNow, kSteadyNow, {});
  PairTracer tracer;
  tracer.Picked(1, kSteadyNow - milliseconds(40));
  tracer.Picked(1, kSteadyNow - milliseconds(10));  // shown again in a later frame
  const ShownPairStamps pair{1, kWallNow - milliseconds(60), kSteadyNow - milliseconds(50),
                             kSteadyNow - milliseconds(48), kSteadyNow - milliseconds(45)};
  const ShowingFrame frame{kSteadyNow - milliseconds(9), kSteadyNow - milliseconds(8),
                           kSteadyNow - milliseconds(4), kSteadyNow};
  EXPECT_EQ(At(tracer.Timeline(pair, std::nullopt, frame, true, to_robot), LatencyStage::kPicked),
            kWallNow - milliseconds(40));
  for (uint64_t s = 2; s < 2 + PairTracer::kRemembered; ++s) tracer.Picked(s, kSteadyNow);
  const PairTimeline forgotten = tracer.Timeline(pair, std::nullopt, frame, false, to_robot);
  EXPECT_FALSE(forgotten.at[static_cast<int>(LatencyStage::kPicked)].has_value());
  EXPECT_FALSE(forgotten.at[static_cast<int>(LatencyStage::kVision)].has_value());
}

TEST(ShownPairStatsTest, PercentilesOfShownPairsAndZeroWhenNone) {
  ShownPairStats stats;
  EXPECT_EQ(stats.DisplayAgePercentileMs(95), 0.0);
  for (int i = 1; i <= 100; ++i) stats.Add(i, 100.0 + i);
  EXPECT_EQ(stats.DisplayAgePercentileMs(50), 50.0);
  EXPECT_EQ(stats.DisplayAgePercentileMs(95), 95.0);
  EXPECT_EQ(stats.FrameTimePercentileMs(95), 195.0);
  EXPECT_EQ(stats.last_display_age_ms(), 100.0);
  EXPECT_EQ(stats.added(), 100u);
  stats.CountOverlay(true, false);
  stats.CountOverlay(false, true);
  stats.CountOverlay(false, false);  // compensation off: neither
  EXPECT_EQ(stats.overlays_moved(), 1u);
  EXPECT_EQ(stats.overlays_faded(), 1u);
}

}  // namespace
}  // namespace mostar::ui
