#include "operator_client/ui/lease_client.h"

#include <gtest/gtest.h>

#include "common/time/fake_clock.h"

namespace mostar::ui {
namespace {

using std::chrono::milliseconds;

ControlLease HeldBy(const std::string& holder) {
  ControlLease lease;
  lease.holder_id = holder;
  return lease;
}

TEST(LeaseClientTest, PilotRequestsUntilItHoldsTheLease) {
  FakeClock clock;
  LeaseClient lease("pilot", /*pilot=*/true);
  EXPECT_EQ(lease.Update(std::nullopt, clock.SteadyNow()), ControlRequest::kTake);
  EXPECT_TRUE(lease.active());
  EXPECT_FALSE(lease.holding());
  // Not answered yet: asked again once per period, not every frame.
  clock.Advance(milliseconds(249));
  EXPECT_EQ(lease.Update(HeldBy("someone-else"), clock.SteadyNow()), ControlRequest::kNone);
  clock.Advance(milliseconds(1));
  EXPECT_EQ(lease.Update(HeldBy("someone-else"), clock.SteadyNow()), ControlRequest::kTake);
  clock.Advance(milliseconds(100));
  EXPECT_EQ(lease.Update(HeldBy("pilot"), clock.SteadyNow()), ControlRequest::kNone);
  EXPECT_TRUE(lease.holding());
  clock.Advance(std::chrono::seconds(5));
  EXPECT_EQ(lease.Update(HeldBy("pilot"), clock.SteadyNow()), ControlRequest::kNone);
}

TEST(LeaseClientTest, PilotAsksAgainAtOnceWhenTheLeaseIsLost) {
  FakeClock clock;
  LeaseClient lease("pilot", true);
  lease.Update(std::nullopt, clock.SteadyNow());
  clock.Advance(milliseconds(2000));
  EXPECT_EQ(lease.Update(HeldBy("pilot"), clock.SteadyNow()), ControlRequest::kNone);
  clock.Advance(milliseconds(100));
  EXPECT_EQ(lease.Update(HeldBy("other"), clock.SteadyNow()), ControlRequest::kTake);
  EXPECT_FALSE(lease.holding());
}

TEST(LeaseClientTest, ObserverNeverAsks) {
  FakeClock clock;
  LeaseClient lease("observer", /*pilot=*/false);
  EXPECT_EQ(lease.Update(std::nullopt, clock.SteadyNow()), ControlRequest::kNone);
  lease.Take();
  clock.Advance(std::chrono::seconds(3));
  EXPECT_EQ(lease.Update(std::nullopt, clock.SteadyNow()), ControlRequest::kNone);
  EXPECT_FALSE(lease.active());
}

TEST(LeaseClientTest, ReleaseStopsRequestsUntilTakenAgain) {
  FakeClock clock;
  LeaseClient lease("pilot", true);
  lease.Update(std::nullopt, clock.SteadyNow());
  EXPECT_EQ(lease.Release(), ControlRequest::kRelease);
  EXPECT_FALSE(lease.active());
  clock.Advance(std::chrono::seconds(5));
  EXPECT_EQ(lease.Update(std::nullopt, clock.SteadyNow()), ControlRequest::kNone);
  // Take asks at the next update, without waiting out the period.
  lease.Take();
  EXPECT_TRUE(lease.active());
  clock.Advance(milliseconds(10));
  EXPECT_EQ(lease.Update(std::nullopt, clock.SteadyNow()), ControlRequest::kTake);
  EXPECT_EQ(lease.Update(std::nullopt, clock.SteadyNow()), ControlRequest::kNone);
  lease.Take();
  EXPECT_EQ(lease.Update(std::nullopt, clock.SteadyNow()), ControlRequest::kTake);
}

TEST(LeaseClientTest, StaysActiveWhileHoldingAfterRelease) {
  // Until the robot's lease shows the release, drive commands keep flowing (stopped).
  FakeClock clock;
  LeaseClient lease("pilot", true);
  lease.Update(HeldBy("pilot"), clock.SteadyNow());
  lease.Release();
  EXPECT_TRUE(lease.active());
  lease.Update(std::nullopt, clock.SteadyNow());
  EXPECT_FALSE(lease.active());
}

TEST(LeaseClientTest, ArmsThreeCommandPeriodsAfterTheLeaseIsHeld) {
  FakeClock clock;
  LeaseClient lease("pilot", true);
  lease.Update(std::nullopt, clock.SteadyNow());
  EXPECT_FALSE(lease.armed(clock.SteadyNow()));
  clock.Advance(milliseconds(700));
  lease.Update(HeldBy("pilot"), clock.SteadyNow());
  clock.Advance(milliseconds(150));
  EXPECT_FALSE(lease.armed(clock.SteadyNow()));
  clock.Advance(milliseconds(1));
  EXPECT_TRUE(lease.armed(clock.SteadyNow()));
  // Losing the lease disarms; holding it again restarts the delay.
  lease.Update(HeldBy("other"), clock.SteadyNow());
  EXPECT_FALSE(lease.armed(clock.SteadyNow()));
  lease.Update(HeldBy("pilot"), clock.SteadyNow());
  clock.Advance(milliseconds(100));
  lease.Update(HeldBy("pilot"), clock.SteadyNow());
  EXPECT_FALSE(lease.armed(clock.SteadyNow()));
}

}  // namespace
}  // namespace mostar::ui
