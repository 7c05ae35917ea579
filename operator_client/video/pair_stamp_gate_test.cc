#include "operator_client/video/pair_stamp_gate.h"

#include <gtest/gtest.h>

namespace mostar::client {
namespace {

using std::chrono::hours;
using std::chrono::milliseconds;
using std::chrono::seconds;

const Time kNow = FromUnixNanos(1'700'000'000'000'000'000);
const SteadyTime kSteady = SteadyTime(seconds(50));

timesync::ClockOffsetEstimate Offset(Duration robot_minus_local, Duration uncertainty) {
  timesync::ClockOffsetEstimate estimate;
  estimate.known = true;
  estimate.responder_minus_requester = robot_minus_local;
  estimate.uncertainty = uncertainty;
  return estimate;
}

TEST(PairStampGateTest, ShowsPairsInCaptureOrderAndRefusesLateOnes) {
  PairStampGate gate;
  EXPECT_EQ(gate.Check(kNow - milliseconds(100), kNow, kSteady), PairVerdict::kShow);
  EXPECT_EQ(gate.Check(kNow - milliseconds(50), kNow, kSteady), PairVerdict::kShow);
  EXPECT_EQ(gate.Check(kNow - milliseconds(80), kNow, kSteady), PairVerdict::kLate);
  EXPECT_EQ(gate.Check(kNow - milliseconds(50), kNow, kSteady), PairVerdict::kLate) << "equal";
  EXPECT_EQ(gate.stats().late, 2u);
}

TEST(PairStampGateTest, RefusesStampsFromTheFutureByTheKnownOffset) {
  PairStampGate gate;  // tolerance 500 ms
  // The robot's clock is 10 s ahead of this machine's, known within 20 ms.
  gate.SetClockOffset(Offset(seconds(10), milliseconds(20)));
  const Time robot_now = kNow + seconds(10);
  EXPECT_EQ(gate.Check(robot_now + hours(1), kNow, kSteady), PairVerdict::kFuture);
  EXPECT_EQ(gate.Check(robot_now + milliseconds(530), kNow, kSteady), PairVerdict::kFuture);
  EXPECT_EQ(gate.stats().future, 2u);
  // Within the tolerance plus the uncertainty, and anything older, is shown.
  EXPECT_EQ(gate.Check(robot_now - milliseconds(80), kNow, kSteady), PairVerdict::kShow);
  EXPECT_EQ(gate.Check(robot_now + milliseconds(510), kNow, kSteady), PairVerdict::kShow);
  // The bad pairs did not freeze anything: the next real pair is shown.
  EXPECT_EQ(gate.Check(robot_now + milliseconds(600), kNow + milliseconds(100), kSteady),
            PairVerdict::kShow);
}

TEST(PairStampGateTest, AnOffsetThatIsNotKnownYetIsIgnored) {
  PairStampGate gate;
  timesync::ClockOffsetEstimate unknown = Offset(seconds(-1000), Duration::zero());
  unknown.known = false;
  gate.SetClockOffset(unknown);
  EXPECT_EQ(gate.Check(kNow, kNow, kSteady), PairVerdict::kShow);
}

TEST(PairStampGateTest, AFuturePairShownBeforeTheOffsetWasKnownIsForgottenOnceItIs) {
  PairStampGate gate;
  EXPECT_EQ(gate.Check(kNow + hours(24), kNow, kSteady), PairVerdict::kShow);  // cannot tell yet
  EXPECT_EQ(gate.Check(kNow, kNow, kSteady), PairVerdict::kLate);
  gate.SetClockOffset(Offset(Duration::zero(), milliseconds(5)));
  EXPECT_EQ(gate.Check(kNow + milliseconds(40), kNow + milliseconds(40), kSteady),
            PairVerdict::kResync);
  EXPECT_EQ(gate.Check(kNow + milliseconds(80), kNow + milliseconds(80), kSteady),
            PairVerdict::kShow);
  EXPECT_EQ(gate.stats().resyncs, 1u);
}

TEST(PairStampGateTest, OnlyLatePairsForLongRestartTheOrderWithoutAnOffset) {
  PairStampGateOptions options;
  options.resync_after = seconds(2);
  PairStampGate gate(options);
  EXPECT_EQ(gate.Check(kNow + hours(24), kNow, kSteady), PairVerdict::kShow);
  // Real pairs at 10 Hz all look late; for 2 s at least, then one restarts the order.
  int late = 0;
  SteadyTime t = kSteady;
  Time stamp = kNow;
  PairVerdict verdict = PairVerdict::kLate;
  while (verdict == PairVerdict::kLate) {
    t += milliseconds(100);
    stamp += milliseconds(100);
    verdict = gate.Check(stamp, stamp, t);
    if (verdict == PairVerdict::kLate) ++late;
  }
  EXPECT_EQ(verdict, PairVerdict::kResync);
  EXPECT_EQ(t - kSteady, seconds(2));
  EXPECT_EQ(late, 19);
  EXPECT_EQ(gate.Check(stamp + milliseconds(100), stamp, t), PairVerdict::kShow);
  // A single late pair after a long pause (an outage) is still late: it needs a streak.
  t += seconds(10);
  EXPECT_EQ(gate.Check(stamp - seconds(1), stamp, t), PairVerdict::kLate);
  EXPECT_EQ(gate.Check(stamp + seconds(1), stamp, t), PairVerdict::kShow);
}

}  // namespace
}  // namespace mostar::client
