#include "common/udp_over_tcp/dial_plan.h"

#include <gtest/gtest.h>

namespace mostar::udp_over_tcp {
namespace {

using std::chrono::milliseconds;
using Time = DialPlan::Clock::time_point;

// A silent path: a new dial every interval beside the pending ones, up to the limit, so one is
// always at most an interval old when the path comes back.
TEST(DialPlanTest, ASilentPathGetsANewDialEveryInterval) {
  DialPlan plan({milliseconds(250), 3, milliseconds(250), milliseconds(1000)});
  const Time t0{};
  int in_flight = 0;
  EXPECT_TRUE(plan.ShouldDial(t0, in_flight));
  plan.Started(t0);
  ++in_flight;
  EXPECT_FALSE(plan.ShouldDial(t0 + milliseconds(249), in_flight));
  EXPECT_TRUE(plan.ShouldDial(t0 + milliseconds(250), in_flight));
  plan.Started(t0 + milliseconds(250));
  ++in_flight;
  plan.Started(t0 + milliseconds(500));
  ++in_flight;
  // Three pending: the limit holds until one of them ends.
  EXPECT_FALSE(plan.ShouldDial(t0 + milliseconds(800), in_flight));
  EXPECT_TRUE(plan.ShouldDial(t0 + milliseconds(800), in_flight - 1));
  EXPECT_EQ(plan.next_dial(), t0 + milliseconds(750));
}

// An answer (refused, unreachable) means the hub is not ready: back off, doubling to the
// maximum; a connection resets it.
TEST(DialPlanTest, AnsweredFailuresBackOffAndAConnectionResetsIt) {
  DialPlan plan({milliseconds(250), 6, milliseconds(100), milliseconds(400)});
  Time now{};
  EXPECT_EQ(plan.Answered(now), milliseconds(100));
  EXPECT_FALSE(plan.ShouldDial(now + milliseconds(99), 0));
  EXPECT_TRUE(plan.ShouldDial(now + milliseconds(100), 0));
  EXPECT_EQ(plan.Answered(now), milliseconds(200));
  EXPECT_EQ(plan.Answered(now), milliseconds(400));
  EXPECT_EQ(plan.Answered(now), milliseconds(400));
  plan.Connected();
  now += milliseconds(10000);
  EXPECT_EQ(plan.Answered(now), milliseconds(100));
}

// A backoff is not shortened by a dial started meanwhile, nor an interval by an answer.
TEST(DialPlanTest, TheLaterOfIntervalAndBackoffWins) {
  DialPlan plan({milliseconds(250), 6, milliseconds(500), milliseconds(1000)});
  const Time t0{};
  plan.Answered(t0);
  plan.Started(t0);
  EXPECT_EQ(plan.next_dial(), t0 + milliseconds(500));
}

}  // namespace
}  // namespace mostar::udp_over_tcp
